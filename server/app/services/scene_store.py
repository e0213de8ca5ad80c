"""Uploaded scenes on disk: RT_DATA_DIR/scenes/<id>/ holds the upload's files,
`scene.json` (the rt.SceneInfo answered to clients) and `stored.json` (where
the scene file is and its content hash, for the workers).
"""

from __future__ import annotations

import io
import json
import secrets
import shutil
import threading
import time
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

import rtcore
from google.protobuf.json_format import Parse
from rt import job_pb2

from ..core.config import Settings
from ..core.proto import to_json_text
from . import scene_cache
from .uploads import StoredUpload, UploadError, store_upload


@dataclass(frozen=True)
class StoredScene:
    info: job_pb2.SceneInfo
    scene_file: Path
    sha256: str

    def load(self) -> rtcore.Scene:
        return scene_cache.get_scene(self.sha256, self.scene_file)


def _scene_info(scene_id: str, name: str, upload: StoredUpload, scene: rtcore.Scene,
                owner: str) -> job_pb2.SceneInfo:
    """What the renderer tells of the scene, and what the upload adds."""
    info = job_pb2.SceneInfo.FromString(scene.info)
    info.MergeFrom(job_pb2.SceneInfo(id=scene_id, name=name, format=upload.format, created_at=time.time(),
                                     size_bytes=upload.size_bytes, owner=owner))
    return info


class SceneStore:
    def __init__(self, settings: Settings):
        self._settings = settings
        self._root = settings.scenes_dir
        self._root.mkdir(parents=True, exist_ok=True)
        self._lock = threading.Lock()
        self._scenes: dict[str, StoredScene] = {}
        for folder in sorted(self._root.iterdir()):
            stored = self._read(folder)
            if stored:
                self._scenes[stored.info.id] = stored

    @staticmethod
    def _read(folder: Path) -> StoredScene | None:
        try:
            info = Parse((folder / "scene.json").read_text(), job_pb2.SceneInfo())
            stored = json.loads((folder / "stored.json").read_text())
            return StoredScene(info, folder / stored["scene_file"], stored["sha256"])
        except (OSError, ValueError, KeyError):
            # A folder left half-written by a crash during an upload.
            shutil.rmtree(folder, ignore_errors=True)
            return None

    def create(self, filename: str, stream: BinaryIO, name: str | None = None, owner: str = "",
               max_bytes: int | None = None) -> StoredScene:
        """Stores and loads an upload of `owner` ("": shared, or the one local
        user's), shown as `name` (default: the file's name), received and
        unpacked up to the server's limits or `max_bytes` if lower (what a
        quota leaves). Raises UploadError (bad file) naming the problem."""
        scene_id = secrets.token_hex(6)
        folder = self._root / scene_id
        files = folder / "files"
        files.mkdir(parents=True)
        try:
            received, unpacked = self._settings.max_upload_bytes, self._settings.max_unpacked_bytes
            if max_bytes is not None:
                received, unpacked = min(received, max_bytes), min(unpacked, max_bytes)
            upload = store_upload(filename, stream, files, max_bytes=received, max_unpacked_bytes=unpacked,
                                  max_files=self._settings.max_upload_files)
            try:
                scene = scene_cache.get_scene(upload.sha256, upload.scene_file)
            except ValueError as e:
                raise UploadError(f"{Path(filename).name}: {e}") from None
            info = _scene_info(scene_id, name or Path(filename).name, upload, scene, owner)
            if upload.left_out:
                shown = ", ".join(upload.left_out[:5]) + (", ..." if len(upload.left_out) > 5 else "")
                info.warnings.append(f"left out {len(upload.left_out)} file(s) of types a scene does not use: {shown}")
            (folder / "stored.json").write_text(json.dumps(
                {"scene_file": str(upload.scene_file.relative_to(folder)), "sha256": upload.sha256}))
            (folder / "scene.json").write_text(to_json_text(info))
        except BaseException:
            shutil.rmtree(folder, ignore_errors=True)
            raise
        stored = StoredScene(info, upload.scene_file, upload.sha256)
        with self._lock:
            self._scenes[scene_id] = stored
        return stored

    def import_samples(self, folder: Path) -> int:
        """Adds the sample scenes (make samples) not stored yet, each through the
        upload path; OBJ scenes travel with their .mtl and sidecar in a zip."""
        known = {s.info.name for s in self.all()}
        added = 0
        for path in sorted(folder.glob("*.glb")) + sorted(folder.glob("*.obj")):
            if path.name in known:
                continue
            if path.suffix == ".glb":
                with path.open("rb") as stream:
                    self.create(path.name, stream)
            else:
                bundle = io.BytesIO()
                with zipfile.ZipFile(bundle, "w") as z:
                    for part in [path] + [path.with_suffix(s) for s in (".mtl", ".rt.json") if path.with_suffix(s).is_file()]:
                        z.write(part, part.name)
                bundle.seek(0)
                self.create(path.stem + ".zip", bundle, name=path.name)
            added += 1
        return added

    def get(self, scene_id: str) -> StoredScene | None:
        with self._lock:
            return self._scenes.get(scene_id)

    def all(self) -> list[StoredScene]:
        """Newest first."""
        with self._lock:
            return sorted(self._scenes.values(), key=lambda s: s.info.created_at, reverse=True)

    def by_hash(self, sha256: str) -> StoredScene | None:
        """A stored scene whose upload hashed to `sha256` (uploads of the same bytes are alike)."""
        with self._lock:
            return next((s for s in self._scenes.values() if s.sha256 == sha256), None)

    def files_folder(self, stored: StoredScene) -> Path:
        """The folder of the scene's own files: its upload's, as stored."""
        return self._root / stored.info.id / "files"

    def delete(self, scene_id: str) -> bool:
        with self._lock:
            stored = self._scenes.pop(scene_id, None)
        if stored is None:
            return False
        if not any(s.sha256 == stored.sha256 for s in self.all()):
            scene_cache.forget(stored.sha256)
        shutil.rmtree(self._root / scene_id, ignore_errors=True)
        return True

    def set_references(self, scene_id: str, job_ids: list[str]) -> StoredScene | None:
        """Replaces the scene's reference jobs, on disk and here; None when the scene is gone."""
        with self._lock:
            stored = self._scenes.get(scene_id)
            if stored is None:
                return None
            info = job_pb2.SceneInfo()
            info.CopyFrom(stored.info)
            del info.reference_jobs[:]
            info.reference_jobs.extend(job_ids)
            path = self._root / scene_id / "scene.json"
            partial = path.with_suffix(".part")
            partial.write_text(to_json_text(info))
            partial.replace(path)
            stored = self._scenes[scene_id] = StoredScene(info, stored.scene_file, stored.sha256)
            return stored

    def model_glb(self, stored: StoredScene) -> Path:
        """The scene as the renderer sees it, as one GLB, written once."""
        path = self._root / stored.info.id / "model.glb"
        if not path.exists():
            data = stored.load().to_glb()
            partial = path.with_suffix(".part")
            partial.write_bytes(data)
            partial.replace(path)
        return path
