"""The generated reference pages (mkdocs-gen-files runs this at every build): a page per node with
its parameters, as its ``--help`` prints them (dsr_graph.ros.parameters.help_text, from the same
declarations the node makes at start), then its module's documentation; and the ``dsr`` and
``clarc`` command lines from their argparse parsers. The parameters and the command lines cannot
drift from the code; the topics and services are what each module's documentation says, checked
against the running nodes by test/system/test_hostile_node.py (test/node_docs.py)."""

from __future__ import annotations

import argparse
import importlib
import inspect
import re
from pathlib import Path

import mkdocs_gen_files

SRC = Path(__file__).resolve().parents[2] / "src"
PACKAGES = ("dsr_graph", "clarc_agents", "clarc_sim")
ENTRY = re.compile(r'"(\w+) = ([\w.]+):main"')


def console_scripts(package: str) -> list[tuple[str, str]]:
    """(executable, module) of a package's console scripts, from its setup.py."""
    return ENTRY.findall((SRC / package / "setup.py").read_text())


def node_class(module):
    from dsr_graph.ros.dsr_node import DsrNode

    found = [
        c
        for _, c in inspect.getmembers(module, inspect.isclass)
        if issubclass(c, DsrNode) and c is not DsrNode and c.__module__ == module.__name__
    ]
    return found[0] if len(found) == 1 else None


def node_pages() -> dict[str, str]:
    """A page per node (reference/nodes/<executable>.md) and their index (reference/nodes.md)."""
    from dsr_graph.ros.parameters import help_text

    index = [
        "# Nodes",
        "",
        "Every node of the suite, by package, each on a page of its own: what `ros2 run",
        "<package> <executable> --help` prints (what the node is, its node name, each parameter",
        "with its type, default, range and whether it is read only at start), then the rest of",
        "its module's documentation (the topics and services it uses, and how it works:",
        "a test checks every topic and service of the running suite's nodes is named there).",
        "Generated from the code at each build of this site. The DSR's own topics: [The DSR",
        "server](dsr-server.md); `ros2 node info /<name>` lists a running node's.",
        "",
    ]
    pages = {}
    for package in PACKAGES:
        index += [f"## {package}", ""]
        for executable, module_name in console_scripts(package):
            module = importlib.import_module(module_name)
            cls = node_class(module)
            if cls is None:
                continue  # a command line, not a node (reference: cli.md)
            summary = inspect.cleandoc(module.__doc__ or "").split("\n\n")[0].replace("\n", " ")
            index.append(f"- [`{executable}`](nodes/{executable}.md): {summary}")
            page = [
                f"# {executable}",
                "",
                f"`ros2 run {package} {executable}` (package `{package}`, module `{module_name}`)",
                "",
                "```text",
                help_text(cls, executable),
                "```",
                "",
            ]
            # the rest of the module's documentation: its topics, services and how it works
            rest = inspect.cleandoc(module.__doc__ or "").split("\n\n", 1)[1:]
            if rest:
                page += ["## Its module's documentation", "", "```text", rest[0].strip(), "```"]
            pages[f"reference/nodes/{executable}.md"] = "\n".join(page) + "\n"
        index.append("")
    pages["reference/nodes.md"] = "\n".join(index)
    return pages


def _helps(parser: argparse.ArgumentParser, prog: str) -> list[str]:
    """The parser's help and each subcommand's, nested."""
    out = [f"### `{prog}`", "", "```text", parser.format_help().rstrip(), "```", ""]
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                out += _helps(sub, f"{prog} {name}")
    return out


def cli_page() -> str:
    from clarc_sim.console.clarc_cli import build_parser as clarc_parser
    from dsr_graph.cli.main import build_parser as dsr_parser

    out = [
        "# Command lines",
        "",
        "`dsr` (the DSR's tools: dsr_graph) and `clarc` (the clinical robot's: clarc_sim), each",
        "command as its `--help` prints it. Generated from their argparse parsers at each build",
        "of this site. What each `dsr` verb is for: [The dsr command line](dsr-cli.md).",
        "",
        "## dsr",
        "",
        *_helps(dsr_parser(), "dsr"),
        "## clarc",
        "",
        *_helps(clarc_parser(), "clarc"),
    ]
    return "\n".join(out)


for path, text in node_pages().items():
    with mkdocs_gen_files.open(path, "w") as f:
        f.write(text)
with mkdocs_gen_files.open("reference/cli.md", "w") as f:
    f.write(cli_page())
