"""The tile stream of one job, as every viewer receives it.

Every tile started and finished is kept (encoded once) in order, so a viewer that connects
late first receives the image so far, tile by tile, and then follows live:
each viewer gets each tile exactly once per pass. The job's record, published as
its state and progress change, is kept only as the latest one: a viewer gets it
after the tiles it has been sent, once per change it has not seen yet, so one
that falls behind or connects late skips the older ones. The stream ends with
the job's final record.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator

from rt import job_pb2


class TileStream:
    def __init__(self) -> None:
        self._messages: list[bytes] = []
        self._end: bytes | None = None
        self._record: bytes = b""
        self._record_version = 0  # how many records were published; the latest is kept
        self._changed = asyncio.Condition()

    @property
    def finished(self) -> bool:
        return self._end is not None

    async def publish(self, message: bytes) -> None:
        """Appends a serialized rt.TileStreamMessage."""
        self._messages.append(message)
        async with self._changed:
            self._changed.notify_all()

    async def update(self, job: job_pb2.Job) -> None:
        """Publishes the job's record as it is now, in place of the one before."""
        self._record = job_pb2.TileStreamMessage(job=job).SerializeToString()
        self._record_version += 1
        async with self._changed:
            self._changed.notify_all()

    async def finish(self, job: job_pb2.Job) -> None:
        self._end = job_pb2.TileStreamMessage(end=job).SerializeToString()
        async with self._changed:
            self._changed.notify_all()

    async def follow(self) -> AsyncIterator[bytes]:
        """Every message from the first, waiting for new ones until the end;
        after the messages sent so far, the latest record if this viewer has
        not had it."""
        sent = record_sent = 0
        while True:
            while sent < len(self._messages):
                sent += 1
                yield self._messages[sent - 1]
            if record_sent < self._record_version:
                record_sent = self._record_version
                yield self._record
                continue  # tiles may have come while it was sent
            if self._end is not None:
                yield self._end
                return
            async with self._changed:
                if sent == len(self._messages) and record_sent == self._record_version and self._end is None:
                    await self._changed.wait()
