"""The vocabulary: which node types, edge types and attributes (with value types) may exist.

It is data (``data/vocabulary.json`` is the default), loaded at start and checked by the graph,
so adding a type needs a file, not a rebuild. A file may say ``"extends": "default"`` to add to
the default instead of replacing it.

Sensor data is declared volatile (``docs/FORMAT.md``, "Volatile values"): an attribute with
``"volatile": true``, and the pose of a node type with ``"volatile_pose": true`` (its RT edge from
its parent, as ``set_rt`` changes it). A change that only sets such values is broadcast without
waiting for the disk and is not journalled; every other change is durable before its writer
hears it was accepted.
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
    volatile: set[str] = field(default_factory=set)  # attributes that hold sensor data
    volatile_poses: set[str] = field(default_factory=set)  # node types whose pose is sensor data

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
        node_types, volatile_poses = _node_types(doc.get("node_types", {}), source)
        vocab = cls(
            node_types=node_types,
            edge_types=_doc_map(doc.get("edge_types", {}), source, "edge_types"),
            volatile_poses=volatile_poses,
        )
        for name, spec in _object(doc.get("attributes", {}), source, "attributes").items():
            if isinstance(spec, str):
                spec = {"type": spec}
            if not isinstance(spec, dict) or spec.get("type") not in VALUE_TYPES:
                raise VocabularyError(
                    f'{source}: attribute {name!r} needs "type" in {list(VALUE_TYPES)}, '
                    f"got {spec!r}"
                )
            unknown = set(spec) - {"type", "doc", "volatile"}
            if unknown:
                raise VocabularyError(
                    f"{source}: attribute {name!r}: unknown keys {sorted(unknown)}"
                )
            if not isinstance(spec.get("volatile", False), bool):
                raise VocabularyError(
                    f'{source}: attribute {name!r}: "volatile" must be true or false'
                )
            vocab.attributes[name] = spec["type"]
            if spec.get("doc"):
                vocab.attribute_docs[name] = str(spec["doc"])
            if spec.get("volatile"):
                vocab.volatile.add(name)
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
            volatile=self.volatile | other.volatile,
            volatile_poses=self.volatile_poses | other.volatile_poses,
        )

    # -- queries ---------------------------------------------------------------------------
    def attribute_type(self, name: str) -> str | None:
        return self.attributes.get(name)

    def to_json(self) -> dict:
        def node_type(name: str, doc: str) -> Any:
            return {"doc": doc, "volatile_pose": True} if name in self.volatile_poses else doc

        def attribute(name: str, type_name: str) -> dict[str, Any]:
            spec: dict[str, Any] = {"type": type_name}
            if name in self.attribute_docs:
                spec["doc"] = self.attribute_docs[name]
            if name in self.volatile:
                spec["volatile"] = True
            return spec

        return {
            "format": FORMAT,
            "version": VERSION,
            "node_types": {n: node_type(n, d) for n, d in sorted(self.node_types.items())},
            "edge_types": dict(sorted(self.edge_types.items())),
            "attributes": {n: attribute(n, t) for n, t in sorted(self.attributes.items())},
        }


def _object(value: Any, source: str, key: str) -> Mapping[str, Any]:
    if not isinstance(value, dict):
        raise VocabularyError(f'{source}: "{key}" must be an object')
    return value


def _node_types(value: Any, source: str) -> tuple[dict[str, str], set[str]]:
    """Node types: a description each, or {"doc", "volatile_pose"}; and those whose pose is
    volatile."""
    docs, volatile = {}, set()
    for name, spec in _object(value, source, "node_types").items():
        if isinstance(spec, dict):
            unknown = set(spec) - {"doc", "volatile_pose"}
            if unknown or not isinstance(spec.get("volatile_pose", False), bool):
                raise VocabularyError(
                    f'{source}: node_types[{name!r}] may say only "doc" and "volatile_pose" '
                    f"(true or false), got {spec!r}"
                )
            if spec.get("volatile_pose"):
                volatile.add(name)
            spec = spec.get("doc", "")
        docs |= _doc_map({name: spec}, source, "node_types")
    return docs, volatile


def _doc_map(value: Any, source: str, key: str) -> dict[str, str]:
    result = {}
    for name, doc in _object(value, source, key).items():
        if not name or not isinstance(doc, str):
            raise VocabularyError(
                f"{source}: {key}[{name!r}] must map a name to a description string"
            )
        result[name] = doc
    return result
