"""Shared fixtures: where the build put the renderer and the sample scenes."""
import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
BUILD = ROOT / "build"
# A build of one's own beside the shared one: RT_SCENES_DIR, RT_RTRENDER.
SCENES = Path(os.environ.get("RT_SCENES_DIR", BUILD / "scenes"))
RTRENDER = Path(os.environ.get("RT_RTRENDER", BUILD / "rtrender"))
ASSETS = Path(os.environ.get("RT_ASSETS_DIR", BUILD / "assets"))


@pytest.fixture(scope="session")
def scenes_dir() -> Path:
    if not (SCENES / "cornell.obj").exists():
        pytest.fail(f"sample scenes missing in {SCENES}: run `make samples`")
    return SCENES


@pytest.fixture(scope="session")
def assets_dir() -> Path:
    """The feature assets of docs/gltf.md (renderer/samples/make_assets.py)."""
    if not (ASSETS / "product.glb").exists():
        pytest.fail(f"test assets missing in {ASSETS}: run `make samples`")
    return ASSETS


@pytest.fixture(scope="session")
def rtrender() -> Path:
    if not RTRENDER.exists():
        pytest.fail(f"{RTRENDER} missing: run `make build`")
    return RTRENDER
