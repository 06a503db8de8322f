"""Where the suite keeps files by default, after the XDG base directories: state (the DSR
server's graph, PELEA's outbox) under $XDG_STATE_HOME, data (the results store) under
$XDG_DATA_HOME."""

from __future__ import annotations

import os


def _home(variable: str, fallback: str) -> str:
    return os.environ.get(variable) or os.path.join(os.path.expanduser("~"), fallback)


def state_path(*parts: str) -> str:
    return os.path.join(_home("XDG_STATE_HOME", ".local/state"), *parts)


def data_path(*parts: str) -> str:
    return os.path.join(_home("XDG_DATA_HOME", ".local/share"), *parts)
