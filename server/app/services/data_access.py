"""How a worker reaches a job's data: through the server's data folder when it
sees it, else over the network.

A worker that mounts the server's data folder (the embedded cluster, or a
cluster on one shared disk) reads the scene's files there and writes its tiles
straight into the job's layer files, so the tiles' floats cross no socket.
Many clusters have no shared POSIX disk (Kubernetes, cloud VMs): a worker
there fetches the scene by its content hash from the server
(api/routes/cluster.py, with the server's cluster secret) and sends its tiles'
layers back in its results, for the server to write.

Each worker chooses for itself, once: it sees the folder when the folder's id
file, which the server writes at start-up, holds the id its tasks carry. The
same path on another machine (a volume of its own mounted at /data, say) holds
another id or none, and a worker that may read but not write the jobs' folder
does not count as seeing it.
"""

from __future__ import annotations

import os
import secrets
import socket
from dataclasses import dataclass
from pathlib import Path

from ..core.config import Settings

FOLDER_ID_FILE = "folder-id"


@dataclass(frozen=True)
class DataAccess:
    """What every tile task carries to reach the job's data either way. The
    cluster secret travels with it: whoever can submit tasks to the Dask
    cluster runs code on its workers, so the cluster is one trust domain."""

    data_dir: str
    folder_id: str
    server_url: str
    secret: str


def server_access(settings: Settings) -> DataAccess:
    """The server's side, made at start-up: the data folder's id (kept across
    restarts, so that workers need not look again) and a new cluster secret."""
    settings.jobs_dir.mkdir(parents=True, exist_ok=True)  # which workers must be able to write
    id_file = settings.data_dir / FOLDER_ID_FILE
    try:
        folder_id = id_file.read_text().strip()
    except FileNotFoundError:
        folder_id = ""
    if not folder_id:
        folder_id = secrets.token_hex(16)
        partial = id_file.with_suffix(".part")
        partial.write_text(folder_id)
        partial.replace(id_file)
    return DataAccess(str(settings.data_dir), folder_id, worker_url(settings), secrets.token_urlsafe(32))


def worker_url(settings: Settings) -> str:
    """Where workers reach the server: RT_SERVER_URL, else its bound address
    (this machine's name when bound to every interface)."""
    if settings.server_url:
        return settings.server_url.rstrip("/")
    host = settings.host if settings.host not in ("0.0.0.0", "::", "") else socket.gethostname()
    return f"http://{f'[{host}]' if ':' in host else host}:{settings.port}"


_sees: dict[tuple[str, str], bool] = {}


def sees_data_folder(access: DataAccess) -> bool:
    """Whether this process sees the server's data folder (and may write its
    jobs' layer files), looked at once per folder."""
    key = (access.data_dir, access.folder_id)
    seen = _sees.get(key)
    if seen is None:
        folder = Path(access.data_dir)
        try:
            same = (folder / FOLDER_ID_FILE).read_text().strip() == access.folder_id
        except OSError:
            same = False
        seen = _sees[key] = same and os.access(folder / "jobs", os.W_OK | os.X_OK)
    return seen
