"""A job's finished images, made from its layer files (layer_files.py): the
last pass (denoising and bloom), image.png, image.exr and the auxiliary layers
as pictures.

Tiles and image.png are encoded to sRGB by the same function (the renderer's
own), so a viewer that paints every tile holds exactly image.png.
"""

from __future__ import annotations

import errno
import io
import shutil
import time
from pathlib import Path

import numpy as np
import rtcore
from PIL import Image
from rt import render_pb2

from . import layer_files


def rgba8(color: np.ndarray, settings: bytes | None = None) -> np.ndarray:
    """Linear RGB floats (h, w, 3) as 8-bit sRGB RGBA, the stream's pixel format,
    through the exposure and tone map of `settings` (serialized
    rt.RenderSettings; None: the defaults)."""
    return rtcore.encode_srgb8(np.ascontiguousarray(color, dtype=np.float32), settings)


def png_bytes(rgba: np.ndarray) -> bytes:
    """Opaque RGB PNG; fast zlib (level 1): it is written while a viewer waits."""
    out = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(rgba[..., :3]), "RGB").save(out, format="PNG", compress_level=1)
    return out.getvalue()


def read_rgba(path: Path) -> np.ndarray:
    """An image file's pixels as RGBA8 (h, w, 4): image.png back as the stream's tiles hold it."""
    return np.asarray(Image.open(path).convert("RGBA"))


def _heat(values: np.ndarray) -> np.ndarray:
    """A perceptual-ish heat ramp (black, purple, orange, yellow, white) over [0, 1]."""
    stops = np.array([[0, 0, 0], [80, 18, 123], [230, 80, 40], [252, 200, 40], [255, 255, 255]], np.float32)
    x = np.clip(values, 0, 1) * (len(stops) - 1)
    i = np.minimum(x.astype(int), len(stops) - 2)
    f = (x - i)[..., None]
    return (stops[i] * (1 - f) + stops[i + 1] * f + 0.5).astype(np.uint8)


def heat_ramp_png(width: int = 256) -> bytes:
    """The heat ramp of bvh_cost.png from low to high, for the viewer's legend."""
    rgb = np.repeat(_heat(np.linspace(0, 1, width, dtype=np.float32))[None], 8, axis=0)
    return png_bytes(np.concatenate([rgb, np.full((8, width, 1), 255, np.uint8)], axis=2))


def aux_preview(name: str, layer: np.ndarray) -> np.ndarray:
    """An auxiliary layer as an RGBA8 picture: depth near-bright, normals as
    colour, albedo in sRGB, alpha as grey, BVH cost (nodes visited) as a heat map."""
    h, w = layer.shape[:2]
    if name == "depth":
        d = layer.reshape(h, w)
        hit = d > 0
        far = float(d[hit].max()) if hit.any() else 1.0
        near = float(d[hit].min()) if hit.any() else 0.0
        gray = np.where(hit, 1.0 - 0.85 * (d - near) / max(far - near, 1e-12), 0.0)
        rgb = np.repeat(gray[..., None], 3, axis=2).astype(np.float32) ** 2.2
        return rgba8(rgb)
    if name == "normal":
        return rgba8(((layer * 0.5 + 0.5) * (np.linalg.norm(layer, axis=2, keepdims=True) > 0)) ** 2.2)
    if name == "albedo":
        return rgba8(layer)
    if name == "alpha":  # coverage as grey levels, 0 black to 1 white
        grey = (np.clip(layer.reshape(h, w), 0, 1) * 255 + 0.5).astype(np.uint8)
        return np.dstack([grey, grey, grey, np.full((h, w), 255, np.uint8)])
    nodes = layer.reshape(h, w, -1)[..., 0].astype(np.float32)
    top = float(np.percentile(nodes, 99.5)) if nodes.size else 1.0
    rgb = _heat(nodes / max(top, 1.0))
    return np.concatenate([rgb, np.full((h, w, 1), 255, np.uint8)], axis=2)


def finish_layers(job_folder: Path, settings: render_pb2.RenderSettings) -> tuple[bytes, float]:
    """The last pass of a job, once every tile is in: denoising, then bloom,
    as `settings` ask, on its colour in place. A denoised job keeps its colour
    before denoising as the "noisy" layer, bloomed as the colour is, so the
    two differ by the denoiser alone. Answers the result's RGBA8 pixels and
    the denoiser's seconds."""
    serialized = settings.SerializeToString()
    color = np.ascontiguousarray(layer_files.load(job_folder, "color", layer_files.PARTIAL))
    seconds = 0.0
    if settings.denoise != render_pb2.NO_DENOISER:
        guides = [np.ascontiguousarray(layer_files.load(job_folder, name, layer_files.PARTIAL))
                  for name in ("albedo", "normal")]
        start = time.perf_counter()
        denoised = rtcore.denoise(color, *guides)
        seconds = time.perf_counter() - start
        layer_files.replace(job_folder, layer_files.NOISY, rtcore.apply_bloom(color, serialized))
        color = denoised
    color = rtcore.apply_bloom(color, serialized)
    layer_files.replace(job_folder, "color", color)
    return rgba8(color, serialized).tobytes(), seconds


def output_file(folder: Path, filename: str, settings: bytes) -> Path:
    """A done job's image.png, image.exr (colour and every auxiliary layer,
    linear) or <layer>.png, made from its layer files the first time it is
    asked for and kept. Encoding them (zip for the EXR, zlib for PNGs) costs
    more than the render's own writing, and many jobs never need most of them,
    so a job is done once its layers are complete. `settings` (the job's,
    serialized) give image.png its exposure and tone map. Callers serialize
    calls for one folder. Raises FileNotFoundError when the job has no such
    layer."""
    path = folder / filename
    if path.is_file():
        return path
    name, suffix = filename.rsplit(".", 1)
    saved = layer_files.names(folder)
    partial = folder / f"part.{filename}"
    if suffix == "exr":
        layers = {layer: np.ascontiguousarray(layer_files.load(folder, layer)) for layer in saved}
        floats = sum(a.nbytes for a in layers.values())
        try:
            rtcore.write_exr(str(partial), layers.pop("color"), layers, layers.pop(layer_files.NOISY, None))
        except RuntimeError as e:
            partial.unlink(missing_ok=True)
            # OpenImageIO says only that the write failed; the image needs about its floats' bytes.
            if shutil.disk_usage(folder).free < floats:
                raise OSError(errno.ENOSPC, "No space left on device", str(partial)) from e
            raise
    else:
        layer = "color" if name == "image" else name
        if layer not in saved:
            raise FileNotFoundError(path)
        values = np.asarray(layer_files.load(folder, layer))
        colour = layer in ("color", layer_files.NOISY)
        picture = rgba8(values, settings) if colour else aux_preview(name, values)
        partial.write_bytes(png_bytes(picture))
    partial.replace(path)
    return path


def layer_bytes(folder: Path, name: str) -> bytes:
    """A done job's linear layer, whole, as a serialized rt.Layer of float32
    with its channels' EXR names: what the viewer's image view reads, the
    values of image.exr without an EXR parser in the browser. Raises
    FileNotFoundError when the job has no such layer."""
    if name not in layer_files.names(folder):
        raise FileNotFoundError(folder / name)
    values = np.ascontiguousarray(layer_files.load(folder, name), dtype="<f4")
    if values.ndim == 2:
        values = values[..., None]
    if name == "color":
        channels = ["R", "G", "B"]
    elif name == layer_files.NOISY:
        channels = [f"{name}.{c}" for c in "RGB"]  # as image.exr names them
    else:
        channels = rtcore.aux_channel_names(name)
    return layer_files.layer_message(name, values, channels).SerializeToString()
