"""Shared test helpers. The suite runs inside `source scripts/env.sh` (scripts/test.sh does it)."""

import os
from pathlib import Path

import pytest
from hypothesis import settings

# CI explores a fixed set of examples (reproducible); a developer's run explores new ones.
settings.register_profile("ci", derandomize=True, print_blob=True)
settings.register_profile("dev", print_blob=True)
settings.load_profile("ci" if os.environ.get("CI") else "dev")

REPO = Path(__file__).resolve().parent.parent
# CI clones the repo with shared/ beside it; a developer tree has it at ../shared too.
SHARED = Path(os.environ.get("DSR_SHARED", REPO.parent / "shared"))
CORTEX_WORLDS = SHARED / "data" / "cortex_worlds"


@pytest.fixture
def cortex_dir():
    if not CORTEX_WORLDS.is_dir():
        pytest.fail(f"shared CORTEX worlds not found at {CORTEX_WORLDS} (set DSR_SHARED)")
    return CORTEX_WORLDS
