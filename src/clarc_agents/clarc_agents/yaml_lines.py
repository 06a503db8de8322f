"""Reading our YAML files strictly (pure): the nodes keep their line numbers, so every mistake
in a scenario or a test definition is an error naming the file and the line."""

from __future__ import annotations

from typing import Any

import yaml

from clarc_agents.exceptions import ScenarioError

# libyaml's safe loader where PyYAML has it (the same documents, parsed in C), else PyYAML's
LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def compose(text: str, source: str, error: type[Exception] = ScenarioError) -> Any:
    """The YAML node tree of ``text``; ``error`` naming the line if it is not YAML."""
    try:
        return yaml.compose(text, Loader=LOADER)
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        line = mark.line + 1 if mark else "?"
        raise error(f"{source}:{line}: not valid YAML: {getattr(e, 'problem', e)}") from None


def err(source: str, node: Any, message: str, error: type[Exception] = ScenarioError) -> Exception:
    """``error`` for ``message`` at ``node``'s line of ``source``."""
    line = (
        node.start_mark.line + 1 if node is not None and getattr(node, "start_mark", None) else "?"
    )
    return error(f"{source}:{line}: {message}")


def scalar(node: Any) -> Any:
    """A scalar node's value with YAML's own typing (int, float, bool, str)."""
    if node is None:
        return None
    return yaml.constructor.SafeConstructor().construct_object(node, deep=True)


def mapping(node: Any) -> dict[str, tuple[Any, Any]]:
    """{key: (key node, value node)} of a mapping node."""
    return {scalar(k): (k, v) for k, v in node.value}


def fields(
    source: str,
    node: Any,
    keys: tuple[str, ...],
    what: str,
    optional: tuple[str, ...] = (),
    error: type[Exception] = ScenarioError,
) -> dict[str, tuple[Any, Any]]:
    """A mapping node's fields, refusing a key it may not have or one of ``keys`` it lacks
    (``what`` says where, e.g. "motion: ")."""
    found = mapping(node)
    for key, (key_node, _) in found.items():
        if key not in keys + optional:
            raise err(
                source,
                key_node,
                f"{what}unknown key {key!r}; the keys are {', '.join(keys + optional)}",
                error,
            )
    missing = [k for k in keys if k not in found]
    if missing:
        raise err(source, node, f"{what}missing {', '.join(missing)}", error)
    return found
