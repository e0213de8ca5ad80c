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
from pathlib import Path

import flip_evaluator
import numpy as np
from rt import job_pb2

from . import layer_files
from .errors import Invalid

# tev's relative MSE: error^2 / (reference^2 + this), so that black pixels do not divide by zero.
RELATIVE_EPSILON = 0.01

_flip_lock = threading.Lock()  # one map at a time: each takes a core for seconds


def _color(folder: Path) -> np.ndarray:
    return np.ascontiguousarray(layer_files.load(folder, "color"), dtype=np.float32)


def _pair(folder: Path, reference_folder: Path, job_id: str, reference_id: str) -> tuple[np.ndarray, np.ndarray]:
    """Both colours, refused unless they are the same size."""
    image, reference = _color(folder), _color(reference_folder)
    if image.shape != reference.shape:
        raise Invalid(f"job '{job_id}' is {image.shape[1]}x{image.shape[0]} and reference '{reference_id}' "
                      f"{reference.shape[1]}x{reference.shape[0]}: compare images of the same size")
    return image, reference


def flip(image: np.ndarray, reference: np.ndarray, folder: Path, reference_id: str) -> tuple[np.ndarray, float]:
    """The HDR-FLIP map (h, w) of a job's colour against the reference's, and
    its mean as flip-evaluator reports it (the number make charts prints);
    kept in the job's folder."""
    cached = folder / "compare" / f"{reference_id}.flip.npz"
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


def compare(folder: Path, reference_folder: Path, job_id: str, reference_id: str,
            rect: tuple[int, int, int, int] | None) -> job_pb2.ImageComparison:
    """The job's colour against the reference's over `rect` (x, y, w, h) or all of it."""
    image, reference = _pair(folder, reference_folder, job_id, reference_id)
    x, y, w, h = region(image.shape[1], image.shape[0], rect)
    window = np.s_[y:y + h, x:x + w]
    error = image[window].astype(np.float64) - reference[window]
    squared = error ** 2
    error_map, whole_mean = flip(image, reference, folder, reference_id)
    mean_flip = whole_mean if rect is None else float(error_map[window].astype(np.float64).mean())
    return job_pb2.ImageComparison(
        job_id=job_id, reference_id=reference_id, x=x, y=y, w=w, h=h,
        rmse=float(np.sqrt(squared.mean())),
        relative_mse=float((squared / (reference[window].astype(np.float64) ** 2 + RELATIVE_EPSILON)).mean()),
        mean_flip=mean_flip)


def flip_layer(folder: Path, reference_folder: Path, job_id: str, reference_id: str) -> bytes:
    """The HDR-FLIP map as a serialized rt.Layer (one float32 channel, "flip")."""
    error_map, _ = flip(*_pair(folder, reference_folder, job_id, reference_id), folder, reference_id)
    values = np.ascontiguousarray(error_map[..., None], dtype="<f4")
    return layer_files.layer_message("flip", values, ["flip"]).SerializeToString()
