"""A stored scene's files as a worker that does not see the data folder asks
for them (api/routes/cluster.py, services/scene_fetch.py)."""

from __future__ import annotations

from pathlib import Path

from rt import job_pb2

from .errors import NotFound
from .scene_store import SceneStore, StoredScene


def _stored(scenes: SceneStore, sha256: str) -> StoredScene:
    stored = scenes.by_hash(sha256)
    if stored is None:
        raise NotFound(f"no stored scene's upload hashed to '{sha256}'")
    return stored


def listing(scenes: SceneStore, sha256: str) -> job_pb2.SceneFiles:
    """Every file of the scene's folder, and the one to load."""
    stored = _stored(scenes, sha256)
    folder = scenes.files_folder(stored)
    files = [job_pb2.StoredFile(path=p.relative_to(folder).as_posix(), size=p.stat().st_size)
             for p in sorted(folder.rglob("*")) if p.is_file()]
    return job_pb2.SceneFiles(scene_file=stored.scene_file.relative_to(folder).as_posix(), files=files)


def file_path(scenes: SceneStore, sha256: str, relative: str) -> Path:
    """One of those files; NotFound for any other path (one leaving the folder included)."""
    folder = scenes.files_folder(_stored(scenes, sha256)).resolve()
    path = (folder / relative).resolve()
    if folder not in path.parents or not path.is_file():
        raise NotFound(f"scene '{sha256}' has no file '{relative}'")
    return path
