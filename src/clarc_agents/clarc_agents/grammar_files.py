"""Where the CLARC agents' grammars are: ``grammars/<agent>.yaml``, installed with the package."""

from __future__ import annotations

from importlib import resources

from dsr_graph.rules.syntax import Rule, load_grammar_file


def grammar_path(agent: str) -> str:
    return str(resources.files("clarc_agents").joinpath(f"grammars/{agent}.yaml"))


def load_grammar(agent: str) -> list[Rule]:
    return load_grammar_file(grammar_path(agent))
