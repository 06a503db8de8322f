"""Every error class of the suite derives from DsrError and is defined in one of the two
exceptions modules (dsr_graph's, and the CLARC packages')."""

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[2] / "src"
HOMES = {
    SRC / "dsr_graph" / "dsr_graph" / "exceptions.py",
    SRC / "clarc_agents" / "clarc_agents" / "exceptions.py",
    SRC / "clarc_sim" / "clarc_sim" / "exceptions.py",
}
BUILTIN_ERRORS = {
    "Exception",
    "ValueError",
    "RuntimeError",
    "LookupError",
    "KeyError",
    "TypeError",
    "OSError",
}


def error_classes():
    for path in sorted(SRC.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef):
                bases = {b.id for b in node.bases if isinstance(b, ast.Name)}
                if (
                    bases & BUILTIN_ERRORS
                    or any(b.endswith("Error") for b in bases)
                    or node.name.endswith("Error")
                ):
                    yield path, node.name


def test_errors_live_in_the_exceptions_modules():
    found = list(error_classes())
    assert len(found) >= 10
    strays = [f"{path.relative_to(SRC)}: {name}" for path, name in found if path not in HOMES]
    assert not strays, strays


def test_every_error_derives_from_dsr_error():
    import clarc_agents.exceptions as clarc
    import clarc_sim.exceptions as stand_ins
    import dsr_graph.exceptions as dsr

    for module in (dsr, clarc, stand_ins):
        for name in dir(module):
            value = getattr(module, name)
            if isinstance(value, type) and issubclass(value, Exception):
                assert issubclass(value, dsr.DsrError), name


def test_echo_shows_whole_messages_or_chosen_fields():
    from dsr_graph.cli.verb.echo import render

    delta = '{"seq": 3, "ops": [{"op": "insert_node", "name": "cup"}]}'
    assert render(delta, [], False) == delta
    assert render(delta, ["ops.0.name"], False) == '"cup"'
    assert render(delta, ["seq", "ops.-1.op"], False) == '{"seq": 3, "ops.-1.op": "insert_node"}'
    assert render(delta, ["ops.5"], False) == '"(missing: ops.5: no item 5)"'
    assert render("not json", ["seq"], False) == "not json"
