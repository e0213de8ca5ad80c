"""What the server makes of a job's tile results as they come back: the
layers of a tile whose worker does not see the data folder, written here, and
the job record's progress."""

from __future__ import annotations

import asyncio
from pathlib import Path

from rt import job_pb2

from . import layer_files
from .layer_files import layer_array
from .tile_plan import TileSpec


async def store_tile(job: job_pb2.Job, layers_dir: Path, spec: TileSpec, result: job_pb2.TileResult) -> None:
    """A full-resolution tile's layers, written by its worker or, sent back by
    one that does not see the data folder, here; counted by the way they came."""
    if result.shared_folder:
        job.tiles_via_shared_folder += 1
        return
    layers = {layer.name: layer_array(layer) for layer in result.layers}
    await asyncio.to_thread(layer_files.write_tile, layers_dir, spec.x, spec.y, layers)
    job.tiles_via_network += 1


class RunProgress:
    """A run's record, brought up to date by each tile that comes back."""

    def __init__(self, job: job_pb2.Job, specs: list[TileSpec]):
        self.job = job
        self.total_pixels = sum(s.pixels for s in specs)
        self.pixels = self.samples = 0

    def add(self, spec: TileSpec, result: job_pb2.TileResult) -> None:
        job = self.job
        job.tiles_done += 1
        # Previews count too: their pixels are part of the image.
        self.pixels += spec.pixels
        self.samples += result.samples
        job.progress = self.pixels / self.total_pixels
        job.mean_samples_per_pixel = self.samples / self.pixels
        job.render_seconds += result.seconds
        job.rays += result.rays
