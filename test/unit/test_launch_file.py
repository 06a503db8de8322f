"""The bringup's launch file (src/clarc_bringup/launch/clarc.launch.py), checked without the
launch wheels (not on PyPI): it parses; it starts the same nodes as scripts/launch.sh, each an
executable of its package, respawned, with parameters its node declares; it names only launch
and launch_ros's public modules. Running it needs a ROS 2 Jazzy install
(docs/how-to/jazzy-install.md)."""

import ast
import importlib
import re
from pathlib import Path

from package_scripts import console_scripts

from dsr_graph.ros.dsr_node import DsrNode
from dsr_graph.ros.parameters import ParameterList

REPO = Path(__file__).resolve().parents[2]
LAUNCH = REPO / "src" / "clarc_bringup" / "launch" / "clarc.launch.py"
PUBLIC = {
    "launch",
    "launch.actions",
    "launch.conditions",
    "launch.substitutions",
    "launch_ros.actions",
    "launch_ros.substitutions",
}


def launched() -> list[tuple[str, str, set[str], bool]]:
    """(package, executable, parameter names, respawned) of every node the file starts."""
    tree = ast.parse(LAUNCH.read_text(), str(LAUNCH))
    nodes = []
    for call in ast.walk(tree):
        if not isinstance(call, ast.Call) or not isinstance(call.func, ast.Name):
            continue
        if call.func.id == "supervised":
            package, executable = (a.value for a in call.args[:2])
            nodes.append((package, executable, {k.arg for k in call.keywords}, True))
        elif call.func.id == "Node":
            kw = {k.arg: k.value for k in call.keywords}
            if not isinstance(kw.get("package"), ast.Constant):
                continue  # the body of supervised(), checked through its callers
            names = set()
            for d in ast.walk(kw.get("parameters", ast.List([]))):
                if isinstance(d, ast.Dict):
                    names |= {k.value for k in d.keys}
            respawn = isinstance(kw.get("respawn"), ast.Constant) and kw["respawn"].value
            nodes.append((kw["package"].value, kw["executable"].value, names, bool(respawn)))
    return nodes


def node_class(module: str) -> type[DsrNode]:
    classes = [
        c
        for c in vars(importlib.import_module(module)).values()
        if isinstance(c, type) and issubclass(c, DsrNode) and c.NAME
    ]
    assert len(classes) == 1, module
    return classes[0]


def test_it_starts_what_launch_sh_starts_each_node_respawned_with_declared_parameters():
    scripts = console_scripts()
    nodes = launched()
    started = set(
        re.findall(r"^\s*start \S+ (\S+)", (REPO / "scripts/launch.sh").read_text(), re.M)
    )
    assert {exe for _, exe, _, _ in nodes} == started | {"clarc_monitor", "clarc"}
    for package, executable, parameters, respawned in nodes:
        assert (package, executable) in scripts, f"{package} has no executable {executable}"
        if executable == "clarc":  # the command line, pressing Start once
            continue
        assert respawned or executable == "clarc_monitor", f"{executable} is not respawned"
        listed = ParameterList(executable)
        node_class(scripts[(package, executable)]).declare_node_parameters(listed)
        declared = {p.name for p in listed.declared}
        assert parameters <= declared, f"{executable}: {parameters - declared} not declared"


def test_it_names_only_public_launch_modules():
    tree = ast.parse(LAUNCH.read_text(), str(LAUNCH))
    modules = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    assert {m for m in modules if m.split(".")[0] in ("launch", "launch_ros")} <= PUBLIC
    assert "generate_launch_description" in {
        f.name for f in tree.body if isinstance(f, ast.FunctionDef)
    }
