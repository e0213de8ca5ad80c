"""Shared fixtures: where the build put the renderer and the sample scenes."""
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
BUILD = ROOT / "build"
SCENES = BUILD / "scenes"


@pytest.fixture(scope="session")
def scenes_dir() -> Path:
    if not (SCENES / "cornell.obj").exists():
        pytest.fail(f"sample scenes missing in {SCENES}: run `make samples`")
    return SCENES


@pytest.fixture(scope="session")
def rtrender() -> Path:
    binary = BUILD / "rtrender"
    if not binary.exists():
        pytest.fail(f"{binary} missing: run `make build`")
    return binary
