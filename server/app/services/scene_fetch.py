"""A scene fetched from the server by a worker that does not see its data
folder (services/data_access.py): the list of the scene's files, then each
file, into a temporary folder that goes once the scene is loaded. The loaded
scene stays in the worker's scene cache; evicted, it is fetched again."""

from __future__ import annotations

import tempfile
from pathlib import Path, PurePosixPath
from urllib.parse import quote

import httpx
import rtcore
from rt import job_pb2

from .data_access import DataAccess

TIMEOUT_SECONDS = 60
CHUNK_BYTES = 1 << 20


class SceneFetchError(RuntimeError):
    pass


def _relative(path: str) -> PurePosixPath:
    """A path the server listed, refused unless it stays inside the folder."""
    parts = PurePosixPath(path)
    if not path or parts.is_absolute() or ".." in parts.parts or "\\" in path or "\0" in path:
        raise SceneFetchError(f"the server listed a scene file outside the scene's folder: {path!r}")
    return parts


def fetch_scene(access: DataAccess, sha256: str) -> rtcore.Scene:
    """The scene whose upload hashed to `sha256`, fetched and loaded. Raises
    SceneFetchError naming the server and the problem."""
    base = f"{access.server_url}/cluster/scenes/{sha256}"
    try:
        with httpx.Client(headers={"Authorization": f"Bearer {access.secret}"}, timeout=TIMEOUT_SECONDS) as client, \
                tempfile.TemporaryDirectory(prefix="rt-scene-") as folder:
            answer = client.get(base)
            answer.raise_for_status()
            listing = job_pb2.SceneFiles.FromString(answer.content)
            for stored in listing.files:
                relative = _relative(stored.path)
                target = Path(folder, *relative.parts)
                target.parent.mkdir(parents=True, exist_ok=True)
                _download(client, f"{base}/files/{quote(stored.path)}", target, stored.size)
            return rtcore.Scene.load(str(Path(folder, *_relative(listing.scene_file).parts)))
    except httpx.HTTPStatusError as e:
        raise SceneFetchError(f"fetching scene {sha256} from {access.server_url}: HTTP {e.response.status_code} "
                              f"{e.response.text[:200]}") from None
    except (httpx.HTTPError, OSError) as e:
        raise SceneFetchError(f"fetching scene {sha256} from {access.server_url}: {e!r}") from None


def _download(client: httpx.Client, url: str, target: Path, size: int) -> None:
    received = 0
    with client.stream("GET", url) as answer, open(target, "wb") as out:
        answer.raise_for_status()
        for chunk in answer.iter_bytes(CHUNK_BYTES):
            received += len(chunk)
            if received > size:
                break
            out.write(chunk)
    if received != size:
        raise SceneFetchError(f"{url}: received {received} bytes, the listing said {size}")
