"""One done job's image against another's of the same size: RMSE, relative
MSE and mean HDR-FLIP, measured as `make charts` measures them
(renderer/bench/accuracy_measure.py), over the whole image or a rectangle;
and the per-pixel HDR-FLIP map the viewer shows as an error map.

The FLIP map is the costly part (about a second for 640x480 on one core),
and a rectangle is measured on the map of the whole image, whose filters see
the pixels around it: so the map is made once per pair, kept in the job's
folder, and every rectangle reads it.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from pathlib import Path

import flip_evaluator
import numpy as np
from rt import job_pb2

from . import layer_files
from .errors import Invalid, NotFound

# tev's relative MSE: error^2 / (reference^2 + this), so that black pixels do not divide by zero.
RELATIVE_EPSILON = 0.01

_flip_lock = threading.Lock()  # one map at a time: each takes a core for seconds


@dataclass(frozen=True)
class Side:
    """One image of a comparison: a done job's folder and which of its colour
    layers ("color", or "noisy": a denoised job's image before denoising)."""
    job_id: str
    folder: Path
    layer: str = "color"

    def load(self) -> np.ndarray:
        try:
            return np.ascontiguousarray(layer_files.load(self.folder, self.layer), dtype=np.float32)
        except FileNotFoundError:
            raise NotFound(f"job '{self.job_id}' has no {self.layer} layer") from None


def _pair(image: Side, reference: Side) -> tuple[np.ndarray, np.ndarray]:
    """Both images, refused unless they are the same size."""
    a, b = image.load(), reference.load()
    if a.shape != b.shape:
        raise Invalid(f"job '{image.job_id}' is {a.shape[1]}x{a.shape[0]} and reference '{reference.job_id}' "
                      f"{b.shape[1]}x{b.shape[0]}: compare images of the same size")
    return a, b


def flip(image: np.ndarray, reference: np.ndarray, sides: tuple[Side, Side]) -> tuple[np.ndarray, float]:
    """The HDR-FLIP map (h, w) of one image against the reference, and its
    mean as flip-evaluator reports it (the number make charts prints); kept
    in the job's folder."""
    mine, theirs = sides
    layers = "" if mine.layer == theirs.layer == "color" else f".{mine.layer}-{theirs.layer}"
    cached = mine.folder / "compare" / f"{theirs.job_id}{layers}.flip.npz"
    with _flip_lock:
        if not cached.is_file():
            error_map, mean, _ = flip_evaluator.evaluate(reference, image, "HDR", applyMagma=False)
            cached.parent.mkdir(exist_ok=True)
            partial = cached.with_suffix(".part.npz")
            np.savez(partial, map=np.asarray(error_map, np.float32).reshape(error_map.shape[:2]), mean=float(mean))
            partial.replace(cached)
        with np.load(cached) as saved:
            return saved["map"], float(saved["mean"])


def region(width: int, height: int, rect: tuple[int, int, int, int] | None) -> tuple[int, int, int, int]:
    """(x, y, w, h) checked against the image; the whole image for None."""
    if rect is None:
        return 0, 0, width, height
    x, y, w, h = rect
    if w <= 0 or h <= 0 or x < 0 or y < 0 or x + w > width or y + h > height:
        raise Invalid(f"region ({x}, {y}, {w}x{h}) is not inside the {width}x{height} image")
    return rect


def compare(mine: Side, theirs: Side, rect: tuple[int, int, int, int] | None) -> job_pb2.ImageComparison:
    """One image against the reference's over `rect` (x, y, w, h) or all of it."""
    image, reference = _pair(mine, theirs)
    x, y, w, h = region(image.shape[1], image.shape[0], rect)
    window = np.s_[y:y + h, x:x + w]
    error = image[window].astype(np.float64) - reference[window]
    squared = error ** 2
    error_map, whole_mean = flip(image, reference, (mine, theirs))
    mean_flip = whole_mean if rect is None else float(error_map[window].astype(np.float64).mean())
    return job_pb2.ImageComparison(
        job_id=mine.job_id, reference_id=theirs.job_id, layer=mine.layer, reference_layer=theirs.layer,
        x=x, y=y, w=w, h=h,
        rmse=float(np.sqrt(squared.mean())),
        relative_mse=float((squared / (reference[window].astype(np.float64) ** 2 + RELATIVE_EPSILON)).mean()),
        mean_flip=mean_flip)


def flip_layer(mine: Side, theirs: Side) -> bytes:
    """The HDR-FLIP map as a serialized rt.Layer (one float32 channel, "flip")."""
    error_map, _ = flip(*_pair(mine, theirs), (mine, theirs))
    values = np.ascontiguousarray(error_map[..., None], dtype="<f4")
    return layer_files.layer_message("flip", values, ["flip"]).SerializeToString()
