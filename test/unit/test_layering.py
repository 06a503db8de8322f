"""The layers of the suite hold: nothing in dsr_graph outside ros/, web/ and cli/ imports rclpy,
a ROS message package or aiohttp, directly (read from the source) or through another module
(imported with those packages made unimportable)."""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src"
DSR = SRC / "dsr_graph" / "dsr_graph"
PLUMBING = ("ros", "web", "cli")  # the only folders of dsr_graph allowed to touch ROS or the web


def is_forbidden(module: str) -> bool:
    top = module.split(".")[0]
    return top in (
        "rclpy",
        "rcl_interfaces",
        "aiohttp",
        "rosidl_runtime_py",
        "launch",
        "launch_ros",
    ) or top.endswith(("_msgs", "_srvs", "_interfaces"))


def pure_modules():
    for path in sorted(DSR.rglob("*.py")):
        rel = path.relative_to(DSR)
        if rel.parts[0] not in PLUMBING:
            yield path, "dsr_graph." + ".".join(rel.with_suffix("").parts).removesuffix(".__init__")


def imports_of(path: Path):
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            yield node.module


def test_the_rule_itself():
    assert (
        is_forbidden("rclpy.node") and is_forbidden("std_msgs.msg") and is_forbidden("dsr_msgs.srv")
    )
    assert (
        is_forbidden("aiohttp.web")
        and not is_forbidden("numpy")
        and not is_forbidden("dsr_graph.model")
    )


def test_no_pure_module_imports_ros_or_the_web_directly():
    offenders = [
        f"{module}: imports {name}"
        for path, module in pure_modules()
        for name in imports_of(path)
        if is_forbidden(name)
    ]
    assert len(list(pure_modules())) > 20
    assert not offenders, "\n".join(offenders)


def test_no_pure_module_needs_ros_or_the_web_through_another_module():
    blocker = (
        "import sys, importlib.abc\n"
        "class Block(importlib.abc.MetaPathFinder):\n"
        "    def find_spec(self, name, path, target=None):\n"
        "        top = name.split('.')[0]\n"
        "        if (top in ('rclpy', 'rcl_interfaces', 'aiohttp')\n"
        "                or top.endswith(('_msgs', '_srvs'))):\n"
        "            raise ImportError(f'{name} is not allowed here')\n"
        "sys.meta_path.insert(0, Block())\n"
        "import importlib\n"
        "for name in sys.argv[1:]:\n"
        "    importlib.import_module(name)\n"
    )
    modules = [module for _, module in pure_modules()]
    done = subprocess.run(
        [sys.executable, "-c", blocker, *modules], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr[-2000:]


@pytest.mark.parametrize(
    "module",
    [
        "clarc_agents.pelea.hle",
        "clarc_agents.pelea.questionnaire_executive",
        "clarc_agents.pelea.gug_executive",
        "clarc_agents.behaviours.speech",
        "clarc_agents.behaviours.panel",
        "clarc_agents.questionnaire.record",
        "clarc_agents.definitions.__init__",
        "clarc_agents.grammar_files",
        "clarc_sim.patient.script",
    ],
)
def test_clarc_logic_is_pure_too(module):
    path = SRC / module.split(".")[0] / Path(*module.split(".")).with_suffix(".py")
    assert not [name for name in imports_of(path) if is_forbidden(name)]


@pytest.mark.parametrize(
    ("module", "not_of"),
    [
        ("hle", ("questionnaire", "gug", "definitions")),
        ("questionnaire_executive", ("gug",)),
        ("gug_executive", ("questionnaire", "definitions")),
    ],
)
def test_each_test_is_a_user_of_the_executive_core_and_of_no_other_test(module, not_of):
    """The core knows no test; a test's executive knows the core, not another test."""
    path = SRC / "clarc_agents" / "clarc_agents" / "pelea" / f"{module}.py"
    imported = set(imports_of(path))
    assert not {
        name for name in imported for other in not_of if name.startswith(f"clarc_agents.{other}")
    }
    assert not {name for name in imported if "_executive" in name}
