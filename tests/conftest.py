"""Shared fixtures: small scenes built in code, and the example files."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# The suite tests numba's path (its dispatchers, signatures and timings are asserted on), in this
# process and the ones it starts; the extension built at install (pounding.aot) is tested on its
# own, with a module each test builds (tests/test_aot.py).
os.environ["POUNDING_AOT"] = "0"
EXAMPLES = ROOT / "examples"


@pytest.fixture
def paper_scene_path() -> Path:
    return EXAMPLES / "paper" / "pair_gap_0.03.toml"


@pytest.fixture(scope="session")
def opensees():
    """The OpenSeesPy module, or a skip where it cannot run (it is a test extra)."""
    from pounding.peer.opensees import load_opensees

    try:
        return load_opensees()
    except ImportError as exc:  # pragma: no cover - depends on the machine
        pytest.skip(f"openseespy unavailable: {exc}")
