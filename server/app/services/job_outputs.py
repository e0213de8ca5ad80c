"""What a job leaves behind and what viewers read of it: its tile stream (a
finished one's image.png as one tile once the server no longer holds it), its
images and linear layers once done, and comparisons of its image with
another's. A part of JobManager (services/jobs.py), which keeps the running.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from pathlib import Path

from rt import job_pb2

from . import comparisons, layer_files
from .errors import Conflict, NotFound
from .job_image import layer_bytes, output_file, read_rgba


class JobOutputs:
    """JobManager's reading side, a base class of it: JobManager provides
    get(), folder(), stream() and _output_lock."""

    async def finished_file(self, job: job_pb2.Job, filename: str) -> Path:
        """output_file for a request: Conflict while the job is not done,
        NotFound when it has no such layer."""
        self.done_folder(job)
        try:
            return await self.output_file(job.id, filename)
        except FileNotFoundError:
            raise _no_layer(job, filename.rsplit(".", 1)[0]) from None

    async def tile_messages(self, job: job_pb2.Job) -> AsyncIterator[bytes]:
        """The job's tile stream as a viewer receives it (serialized
        rt.TileStreamMessage): its TileStream, live or kept; for a finished job
        no longer held in memory, its image.png as one tile, then the record."""
        stream = self.stream(job.id)
        if stream is not None:
            async for message in stream.follow():
                yield message
            return
        rgba = None
        if job.state == job_pb2.DONE:
            try:
                rgba = await asyncio.to_thread(read_rgba, await self.output_file(job.id, "image.png"))
            except FileNotFoundError:
                pass  # the stream still ends with the record
        for message in final_image_stream(job, rgba):
            yield message

    def done_folder(self, job: job_pb2.Job) -> Path:
        """A job's folder, for what exists once it is done: Conflict before."""
        if job.state != job_pb2.DONE:
            raise Conflict(f"job '{job.id}' is {job_pb2.JobState.Name(job.state).lower()}: "
                           "its image exists once it is done")
        return self.folder(job.id)

    def side(self, job: job_pb2.Job, layer: str = "color") -> comparisons.Side:
        """One image of a comparison: a done job's colour layer (Conflict while it is not done)."""
        return comparisons.Side(job.id, self.done_folder(job), layer)

    async def compare(self, mine: comparisons.Side, theirs: comparisons.Side,
                      rect: tuple[int, int, int, int] | None) -> job_pb2.ImageComparison:
        """One job's image measured against another's (comparisons.compare)."""
        return await asyncio.to_thread(comparisons.compare, mine, theirs, rect)

    async def flip_layer(self, mine: comparisons.Side, theirs: comparisons.Side) -> bytes:
        """The HDR-FLIP map of one job's image against another's, as a serialized rt.Layer."""
        return await asyncio.to_thread(comparisons.flip_layer, mine, theirs)

    async def layer(self, job: job_pb2.Job, name: str) -> bytes:
        """A done job's linear layer as a serialized rt.Layer: Conflict while
        the job is not done, NotFound when it has no such layer."""
        folder = self.done_folder(job)
        try:
            return await asyncio.to_thread(layer_bytes, folder, name)
        except FileNotFoundError:
            raise _no_layer(job, name) from None

    async def output_file(self, job_id: str, filename: str) -> Path:
        """A done job's image.png, image.exr or <layer>.png, made when first
        asked for (job_image.output_file); raises FileNotFoundError when the job
        has no such layer. One at a time: making one is CPU-bound, and two
        requests for the same file must not both make it."""
        settings = self.get(job_id).request.settings.SerializeToString()
        async with self._output_lock:
            return await asyncio.to_thread(output_file, self.folder(job_id), filename, settings)


def _no_layer(job: job_pb2.Job, name: str) -> NotFound:
    how = "settings.denoise" if name == layer_files.NOISY else "the request's outputs"
    return NotFound(f"job '{job.id}' has no {name} layer (ask for it in {how})")


def final_image_stream(job: job_pb2.Job, rgba) -> list[bytes]:
    """The stream of a finished job no longer held in memory: the whole image
    as one tile, then the record."""
    messages = []
    if rgba is not None:
        h, w = rgba.shape[:2]
        messages.append(whole_image_tile(job.id, max(job.passes, 1) - 1, w, h, rgba.tobytes()))
    messages.append(job_pb2.TileStreamMessage(end=job).SerializeToString())
    return messages


def whole_image_tile(job_id: str, pass_index: int, width: int, height: int, rgba: bytes) -> bytes:
    """The stream's message for a whole image (RGBA8 bytes) as one tile of `pass_index`."""
    region = job_pb2.TileRegion(**{"pass": pass_index}, x=0, y=0, w=width, h=height)
    tile = job_pb2.Tile(job=job_id, region=region, scale=1, pixels=rgba)
    return job_pb2.TileStreamMessage(tile=tile).SerializeToString()
