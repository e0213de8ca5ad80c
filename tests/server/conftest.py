"""Makes the job service importable as `app`, as it is when run from server/."""
import sys
from pathlib import Path

SERVER = str(Path(__file__).resolve().parents[2] / "server")
if sys.path[0] != SERVER:
    sys.path.insert(0, SERVER)

import io
import zipfile

import pytest
from fastapi.testclient import TestClient

from app.main import create_app
from live_server import live_server  # noqa: F401  (a fixture: `python -m app` on a free port)
from service import service_settings


@pytest.fixture(scope="session")
def client(tmp_path_factory):
    """One service (embedded Dask cluster) for the API tests, on its own data folder."""
    with TestClient(create_app(service_settings(tmp_path_factory.mktemp("data")))) as client:
        yield client


@pytest.fixture(scope="session")
def cornell_zip(scenes_dir) -> bytes:
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for name in ("cornell.obj", "cornell.mtl", "cornell.rt.json"):
            z.write(scenes_dir / name, name)
    return out.getvalue()


@pytest.fixture(scope="session")
def cornell_id(client, cornell_zip) -> str:
    response = client.post("/api/scenes", files={"file": ("cornell.zip", cornell_zip)})
    assert response.status_code == 201, response.text
    return response.json()["id"]


@pytest.fixture(scope="session")
def dragon_id(client, scenes_dir) -> str:
    with open(scenes_dir / "dragon_2.glb", "rb") as f:
        response = client.post("/api/scenes", files={"file": ("dragon_2.glb", f)})
    assert response.status_code == 201, response.text
    return response.json()["id"]
