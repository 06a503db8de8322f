"""The layers are in order (docs/explanation/architecture.md, "The house"): every import between
the project's modules (at the top or inside a function; not those under ``if TYPE_CHECKING``)
goes down or sideways, never up, in the packages' order and in each package's folders' order;
and no two modules import each other, directly or round a longer loop. Checking each arrow is
enough: an order has no way back up through other modules."""

import ast
import itertools
import sys
from pathlib import Path

SRC = Path(__file__).resolve().parents[2] / "src"
PACKAGES = ("dsr_graph", "clarc_agents", "clarc_sim", "clarc_bringup")
# each package's folders (and top-level modules), lowest first; one level may hold several
LEVELS = {
    "dsr_graph": (
        ("exceptions", "data", "model"),
        ("formats",),
        ("protocol",),
        ("rules", "web"),
        ("ros",),
        ("cli",),
    ),
    "clarc_agents": (
        ("exceptions", "sentence", "topics", "data", "grammars"),
        ("yaml_lines",),
        ("languages",),
        ("definitions", "test_node"),
        ("questionnaire", "gug"),
        ("asr", "behaviours", "humans", "grammar_files"),
        ("pelea",),
        ("course",),
        ("nodes",),
    ),
    "clarc_sim": (
        ("exceptions", "sim_topics"),
        ("patient",),
        ("devices", "hospital"),
        ("console",),
    ),
}


def modules(src: Path) -> dict[str, Path]:
    out = {}
    for package in PACKAGES:
        root = src / package / package
        for path in sorted(root.rglob("*.py")):
            if "node_modules" not in path.parts:
                name = ".".join(path.relative_to(root.parent).with_suffix("").parts)
                out[name.removesuffix(".__init__")] = path
    return out


def _type_only(tree: ast.AST) -> set[int]:
    return {
        id(inner)
        for node in ast.walk(tree)
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)
        for inner in ast.walk(node)
    }


def imports(name: str, path: Path, known: dict[str, Path]) -> set[str]:
    """The project's modules ``name`` imports (relative imports resolved)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skipped = _type_only(tree)
    found = set()
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = name.split(".")[: None if path.name == "__init__.py" else -1]
                parts = parts[: len(parts) - node.level + 1]
                base = ".".join([*parts, *([base] if base else [])])
            found.add(base)
            found.update(f"{base}.{alias.name}" for alias in node.names)
    return {m for m in found if m in known and m != name}


def arrows(src: Path) -> dict[str, set[str]]:
    known = modules(src)
    return {name: imports(name, path, known) for name, path in known.items()}


def _level(module: str) -> tuple[int, int | None]:
    package, *rest = module.split(".")
    folder = rest[0] if rest else None
    for k, members in enumerate(LEVELS.get(package, ())):
        if folder in members:
            return PACKAGES.index(package), k
    return PACKAGES.index(package), None


def upward(graph: dict[str, set[str]]) -> list[str]:
    """Every arrow against the order, and every folder the order does not place."""
    out = []
    for source, targets in sorted(graph.items()):
        here = _level(source)
        if here[1] is None and "." in source and source.split(".")[0] in LEVELS:
            out.append(f"{source}: its folder has no place in LEVELS")
        for target in sorted(targets):
            there = _level(target)
            if there[0] > here[0]:
                out.append(f"{source} -> {target}: a package above it")
            elif there[0] == here[0] and None not in (here[1], there[1]) and there[1] > here[1]:
                out.append(f"{source} -> {target}: a layer above it")
    return out


def loops(graph: dict[str, set[str]]) -> list[list[str]]:
    """The modules that reach each other (Tarjan's strongly connected components)."""
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10 * len(graph)))
    index, low, stack, on, found, counter = {}, {}, [], set(), [], itertools.count()

    def visit(v):
        index[v] = low[v] = next(counter)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while not component or component[-1] != v:
                component.append(stack.pop())
                on.discard(component[-1])
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_every_import_goes_down_the_layers():
    graph = arrows(SRC)
    assert len(graph) > 150 and sum(map(len, graph.values())) > 400
    assert not upward(graph), "\n".join(upward(graph))


def test_no_modules_import_each_other():
    assert not loops(arrows(SRC))


def _plant(tmp_path: Path, files: dict[str, str]) -> Path:
    for rel, text in files.items():
        path = tmp_path / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return tmp_path


def test_a_planted_upward_import_or_loop_is_caught(tmp_path):
    src = _plant(
        tmp_path,
        {
            "dsr_graph/dsr_graph/__init__.py": "",
            "dsr_graph/dsr_graph/model/__init__.py": "",
            "dsr_graph/dsr_graph/model/graph.py": "def f():\n    from ..ros import agent\n",
            "dsr_graph/dsr_graph/ros/__init__.py": "",
            "dsr_graph/dsr_graph/ros/agent.py": "from dsr_graph.model import graph\n",
            "dsr_graph/dsr_graph/protocol/__init__.py": "",
            "dsr_graph/dsr_graph/protocol/typed.py": (
                "from typing import TYPE_CHECKING\n"
                "if TYPE_CHECKING:\n    from dsr_graph.cli import main\n"
            ),
            "dsr_graph/dsr_graph/cli/__init__.py": "",
            "dsr_graph/dsr_graph/cli/main.py": "import dsr_graph.protocol.typed\n",
            "clarc_sim/clarc_sim/__init__.py": "",
            "clarc_sim/clarc_sim/patient/__init__.py": "",
            "clarc_sim/clarc_sim/patient/p.py": "from clarc_sim.devices import d\n",
            "clarc_sim/clarc_sim/devices/__init__.py": "",
            "clarc_sim/clarc_sim/devices/d.py": "from clarc_sim.patient import p\n",
            "clarc_agents/clarc_agents/__init__.py": "",
            "clarc_agents/clarc_agents/pelea/__init__.py": "",
            "clarc_agents/clarc_agents/pelea/x.py": "import clarc_sim.patient.p\n",
        },
    )
    graph = arrows(src)
    # ("from package import module" runs the package's __init__ too: two arrows)
    assert upward(graph) == [
        "clarc_agents.pelea.x -> clarc_sim.patient.p: a package above it",
        "clarc_sim.patient.p -> clarc_sim.devices: a layer above it",
        "clarc_sim.patient.p -> clarc_sim.devices.d: a layer above it",
        "dsr_graph.model.graph -> dsr_graph.ros: a layer above it",
        "dsr_graph.model.graph -> dsr_graph.ros.agent: a layer above it",
    ]
    # the type-only import is no arrow; the two real loops are found
    assert loops(graph) == [
        ["clarc_sim.devices.d", "clarc_sim.patient.p"],
        ["dsr_graph.model.graph", "dsr_graph.ros.agent"],
    ]
