"""Reading and writing world files in either format, detected from the content."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Any, NamedTuple

from dsr_graph.exceptions import FormatError, Violation, WorldLoadError
from dsr_graph.formats import cortex, dsr_json
from dsr_graph.formats.private_files import current_umask
from dsr_graph.model.binary import to_json_value
from dsr_graph.model.graph import Graph
from dsr_graph.model.vocabulary import Vocabulary

FORMATS = ("dsr", "cortex")


class LoadedWorld(NamedTuple):
    graph: Graph
    violations: list[Violation]  # what was left out, and why; empty for a valid world
    format: str  # "dsr" or "cortex"


def detect_format(doc: Any) -> str:
    if dsr_json.is_dsr_document(doc):
        return "dsr"
    if cortex.is_cortex_document(doc):
        return "cortex"
    raise WorldLoadError(
        'not a world file: expected {"format": "dsr-graph", ...} or {"DSRModel": ...}'
    )


def parse_world(
    doc: Any, vocabulary: Vocabulary | None = None, source: str = "world"
) -> LoadedWorld:
    fmt = detect_format(doc)
    try:
        if fmt == "dsr":
            graph, violations = dsr_json.from_json(doc, vocabulary, source)
        else:
            graph, violations = cortex.from_cortex(doc, vocabulary, source)
    except FormatError as e:
        raise WorldLoadError(str(e)) from e
    return LoadedWorld(graph, violations, fmt)


def read_world(path: str | Path, vocabulary: Vocabulary | None = None) -> LoadedWorld:
    """Load a world file (ours or CORTEX). Raises ``WorldLoadError`` only when nothing can be
    read."""
    try:
        text = Path(path).read_text("utf-8")
    except OSError as e:
        raise WorldLoadError(f"cannot read {path}: {e.strerror}") from e
    except UnicodeDecodeError as e:
        raise WorldLoadError(f"{path} is not UTF-8 text: {e}") from e
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        raise WorldLoadError(f"{path} is not JSON: {e}") from e
    return parse_world(doc, vocabulary, source=os.path.basename(str(path)))


def world_document(graph: Graph, fmt: str = "dsr") -> dict:
    if fmt == "dsr":
        return dsr_json.to_json(graph, kind="world")
    if fmt == "cortex":
        return cortex.to_cortex(graph)
    raise ValueError(f"format must be one of {FORMATS}, got {fmt!r}")


def write_json_atomically(doc: Any, path: str | Path, indent: int | None = 2) -> None:
    """Write JSON so that a crash leaves either the old file or the new one, never half of one."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=str(path.parent or "."), prefix=f".{path.name}.", suffix=".tmp")
    os.fchmod(fd, 0o666 & ~current_umask())  # mkstemp makes 0600; the umask decides
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            json.dump(
                doc,
                f,
                indent=indent,
                separators=None if indent else (",", ":"),
                default=to_json_value,
            )
            f.write("\n")
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_world(graph: Graph, path: str | Path, fmt: str = "dsr") -> None:
    write_json_atomically(world_document(graph, fmt), path)
