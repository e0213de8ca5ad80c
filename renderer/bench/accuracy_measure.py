"""Timed renders through rtcore, converged references cached on disk, the two
error measures (RMSE on the linear image, mean HDR-FLIP) and the machine the
numbers come from."""

from __future__ import annotations

import datetime
import hashlib
import json
import os
import platform
import re
import statistics
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

import flip_evaluator
import numpy as np
import rtcore
from google.protobuf import json_format
from rt import job_pb2, render_pb2


@dataclass(frozen=True)
class SceneSpec:
    label: str          # as the charts name it
    path: Path
    camera: str = ""    # a camera the scene names; empty: its default view


def settings_bytes(fields: dict) -> bytes:
    """rt.RenderSettings from its JSON form (snake_case names, enum names as strings)."""
    message = json_format.ParseDict(fields, render_pb2.RenderSettings())
    return message.SerializeToString(deterministic=True)


def rmse(reference: np.ndarray, image: np.ndarray) -> float:
    return float(np.sqrt(np.mean((image.astype(np.float64) - reference) ** 2)))


def mean_flip(reference: np.ndarray, image: np.ndarray) -> float:
    """Mean HDR-FLIP of linear images; its exposure range comes from the reference."""
    _, mean, _ = flip_evaluator.evaluate(np.ascontiguousarray(reference), np.ascontiguousarray(image), "HDR",
                                         applyMagma=False)
    return float(mean)


def _git(*args: str) -> str:
    root = Path(__file__).resolve().parents[2]
    result = subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True, check=False)
    return result.stdout.strip() if result.returncode == 0 else ""


def machine_info() -> dict:
    """CPU, cores, date, commit (with `+dirty` for uncommitted changes) and the
    load average when the run started: other work on the cores skews times."""
    cpu = next((line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                if line.startswith("model name")), platform.processor() or "unknown")
    commit = _git("rev-parse", "--short=12", "HEAD") or "unknown"
    # The charts themselves change as a run writes them: only the code counts.
    if _git("status", "--porcelain", "--untracked-files=no", "--", ".", ":!docs/charts"):
        commit += "+dirty"
    return {"cpu": cpu, "cores": os.cpu_count(), "date": datetime.datetime.now().astimezone().isoformat("T", "seconds"),
            "commit": commit, "load_average": " ".join(f"{v:.2f}" for v in os.getloadavg()),
            "python": platform.python_version(), "os": platform.platform(terse=True)}


def _file_digest(path: Path) -> str:
    return hashlib.sha1(path.read_bytes()).hexdigest()


class Renderer:
    """Loads each scene once, times renders on every core and caches the
    converged references in `cache`, keyed by the scene's files, the camera,
    the settings and the rtcore build (a rebuilt renderer renders them anew)."""

    def __init__(self, cache: Path, repeats: bool = True, tile_size: int = 32):
        self.cache = cache
        self.repeats = repeats
        self.tile_size = tile_size
        self._scenes: dict[SceneSpec, tuple[object, bytes, str]] = {}
        self._module = _file_digest(Path(rtcore.__file__))

    def _load(self, spec: SceneSpec) -> tuple[object, bytes, str]:
        if spec not in self._scenes:
            scene = rtcore.Scene.load(str(spec.path))
            if spec.camera:
                cameras = {c.name: c.camera.SerializeToString()
                           for c in job_pb2.SceneInfo.FromString(scene.info).cameras}
                if spec.camera not in cameras:
                    raise SystemExit(f"speed_accuracy: {spec.path.name} has no camera {spec.camera!r} "
                                     f"(it has {', '.join(cameras) or 'none'})")
                camera = cameras[spec.camera]
            else:
                camera = scene.default_camera
            # The scene file and every file beside it of the same stem: .mtl, .rt.json.
            files = sorted(p for p in spec.path.parent.glob(f"{spec.path.stem}.*") if p.is_file())
            digest = hashlib.sha1("".join(p.name + _file_digest(p) for p in files).encode()).hexdigest()
            scene.render(camera, settings_bytes({"width": 16, "height": 16}), 0, self.tile_size)  # warm-up
            self._scenes[spec] = (scene, camera, digest)
        return self._scenes[spec]

    def render(self, spec: SceneSpec, fields: dict) -> tuple[np.ndarray, float]:
        """One render on all cores: (image, wall seconds)."""
        scene, camera, _ = self._load(spec)
        data = settings_bytes(fields)
        start = time.perf_counter()
        image = scene.render(camera, data, 0, self.tile_size)
        return image, time.perf_counter() - start

    def timed(self, spec: SceneSpec, fields: dict, budget_s: float = 1.0,
              most: int = 5) -> tuple[np.ndarray, float, int]:
        """(image, median wall seconds, renders timed): a short render is
        repeated, up to `most` times, until about `budget_s` has been spent."""
        image, seconds = self.render(spec, fields)
        times = [seconds]
        while self.repeats and len(times) < most and sum(times) + times[0] <= budget_s:
            times.append(self.render(spec, fields)[1])
        return image, statistics.median(times), len(times)

    def mean_samples(self, spec: SceneSpec, fields: dict, every: int = 4) -> float:
        """Camera samples per pixel an adaptive render takes, counted on every
        `every`-th pixel each way (a preview tile: pixels are independent)."""
        scene, camera, _ = self._load(spec)
        width, height = fields["width"], fields["height"]
        counted = scene.render_tile(camera, settings_bytes(fields), 0, 0, width, height, aux=[], scale=every)
        return counted["samples"] / (-(-width // every) * -(-height // every))

    def reference(self, spec: SceneSpec, fields: dict) -> tuple[np.ndarray, float, bool]:
        """(image, seconds it took, whether it came from the cache)."""
        _, camera, scene_digest = self._load(spec)
        key = hashlib.sha1(b"|".join([scene_digest.encode(), camera, settings_bytes(fields),
                                      self._module.encode()])).hexdigest()[:16]
        stem = re.sub(r"[^A-Za-z0-9]+", "_", spec.label).strip("_") + f"-{key}"
        image_file, meta_file = self.cache / f"{stem}.npy", self.cache / f"{stem}.json"
        if image_file.exists() and meta_file.exists():
            return np.load(image_file), json.loads(meta_file.read_text())["seconds"], True
        image, seconds = self.render(spec, fields)
        self.cache.mkdir(parents=True, exist_ok=True)
        np.save(image_file, image)
        meta_file.write_text(json.dumps({"scene": str(spec.path), "camera": spec.camera or "default",
                                         "settings": fields, "seconds": seconds}, indent=2) + "\n")
        # A look at it, for whoever wonders what the errors are measured against.
        from PIL import Image
        Image.fromarray(rtcore.encode_srgb8(image)[..., :3]).save(self.cache / f"{stem}.png")
        return image, seconds, False
