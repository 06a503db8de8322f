"""The vocabulary: which node types, edge types and attributes (with value types) may exist.

It is data (``data/vocabulary.json`` is the default), loaded at start and checked by the graph,
so adding a type needs a file, not a rebuild. A file may say ``"extends": "default"`` to add to
the default instead of replacing it.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from dsr_graph.exceptions import VocabularyError
from dsr_graph.model.values import VALUE_TYPES

FORMAT = "dsr-vocabulary"
VERSION = 1
RT = "RT"  # the fixed label of geometric edges (paper, Section II-A)


@dataclass
class Vocabulary:
    node_types: dict[str, str] = field(default_factory=dict)  # type -> doc
    edge_types: dict[str, str] = field(default_factory=dict)  # type -> doc
    attributes: dict[str, str] = field(default_factory=dict)  # name -> value type
    attribute_docs: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.edge_types.setdefault(
            RT, "geometric edge: the child's rigid pose in the parent's frame"
        )

    # -- loading ---------------------------------------------------------------------------
    @classmethod
    def default(cls) -> Vocabulary:
        text = resources.files("dsr_graph").joinpath("data/vocabulary.json").read_text("utf-8")
        return cls.from_json(json.loads(text), source="default vocabulary")

    @classmethod
    def load(cls, path: str | Path | None) -> Vocabulary:
        """The vocabulary in ``path``, or the default when ``path`` is empty or None."""
        if not path:
            return cls.default()
        try:
            doc = json.loads(Path(path).read_text("utf-8"))
        except OSError as e:
            raise VocabularyError(f"cannot read vocabulary file {path}: {e.strerror}") from e
        except json.JSONDecodeError as e:
            raise VocabularyError(f"vocabulary file {path} is not JSON: {e}") from e
        return cls.from_json(doc, source=str(path))

    @classmethod
    def from_json(cls, doc: Any, source: str = "vocabulary") -> Vocabulary:
        if not isinstance(doc, dict):
            raise VocabularyError(f"{source}: top level must be an object")
        if doc.get("format") != FORMAT:
            raise VocabularyError(f'{source}: "format" must be "{FORMAT}"')
        if doc.get("version") != VERSION:
            raise VocabularyError(
                f"{source}: unsupported version {doc.get('version')!r} (this is {VERSION})"
            )
        unknown = set(doc) - {
            "format",
            "version",
            "doc",
            "extends",
            "node_types",
            "edge_types",
            "attributes",
        }
        if unknown:
            raise VocabularyError(f"{source}: unknown keys {sorted(unknown)}")
        vocab = cls(
            node_types=_doc_map(doc.get("node_types", {}), source, "node_types"),
            edge_types=_doc_map(doc.get("edge_types", {}), source, "edge_types"),
        )
        for name, spec in _object(doc.get("attributes", {}), source, "attributes").items():
            if isinstance(spec, str):
                spec = {"type": spec}
            if not isinstance(spec, dict) or spec.get("type") not in VALUE_TYPES:
                raise VocabularyError(
                    f'{source}: attribute {name!r} needs "type" in {list(VALUE_TYPES)}, '
                    f"got {spec!r}"
                )
            vocab.attributes[name] = spec["type"]
            if spec.get("doc"):
                vocab.attribute_docs[name] = str(spec["doc"])
        extends = doc.get("extends")
        if extends is None:
            return vocab
        if extends != "default":
            raise VocabularyError(f'{source}: "extends" may only be "default", got {extends!r}')
        return cls.default().merged(vocab, source)

    def merged(self, other: Vocabulary, source: str = "vocabulary") -> Vocabulary:
        """This vocabulary plus ``other``; an attribute may not change its value type."""
        for name, type_name in other.attributes.items():
            mine = self.attributes.get(name)
            if mine is not None and mine != type_name:
                raise VocabularyError(
                    f"{source}: attribute {name!r} is {mine} in the base vocabulary, "
                    f"cannot become {type_name}"
                )
        return Vocabulary(
            node_types={**self.node_types, **other.node_types},
            edge_types={**self.edge_types, **other.edge_types},
            attributes={**self.attributes, **other.attributes},
            attribute_docs={**self.attribute_docs, **other.attribute_docs},
        )

    # -- queries ---------------------------------------------------------------------------
    def attribute_type(self, name: str) -> str | None:
        return self.attributes.get(name)

    def to_json(self) -> dict:
        return {
            "format": FORMAT,
            "version": VERSION,
            "node_types": dict(sorted(self.node_types.items())),
            "edge_types": dict(sorted(self.edge_types.items())),
            "attributes": {
                name: (
                    {"type": t, "doc": self.attribute_docs[name]}
                    if name in self.attribute_docs
                    else {"type": t}
                )
                for name, t in sorted(self.attributes.items())
            },
        }


def _object(value: Any, source: str, key: str) -> Mapping[str, Any]:
    if not isinstance(value, dict):
        raise VocabularyError(f'{source}: "{key}" must be an object')
    return value


def _doc_map(value: Any, source: str, key: str) -> dict[str, str]:
    result = {}
    for name, doc in _object(value, source, key).items():
        if not name or not isinstance(doc, str):
            raise VocabularyError(
                f"{source}: {key}[{name!r}] must map a name to a description string"
            )
        result[name] = doc
    return result
