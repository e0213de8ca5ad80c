"""Fair share between named users: a user who posts a thousand jobs does not
hold up another user's one job by more than a tile.

Dask runs the queued task of highest priority first (the scheduler's queue of
root-ish tasks and each worker's ready heap are both ordered by the
`priority` annotation, then by graph generation, older first). tile_plan's
priorities rank tiles by their index within a job, so the tiles of equal
index of every queued job tie and the older graphs go first: behind a user's
thousand queued jobs, another user's first tile waited for a thousand tiles.

With named users every tile instead gets a tag, its place in its user's queue
on one virtual clock (start-time fair queuing, at tile granularity): a job's
tiles are numbered on from the later of the clock and the end of the user's
own jobs still queued, in their plan's order (previews first, centre out),
and its priority is the interactive boost minus the tag. The clock is the
largest tag a worker has started on. A user's jobs thus run one after the
other, and users take turns tile by tile: a newcomer's first tile is numbered
at the clock, below every tile still queued, so it runs as soon as a thread
is free; its next ones interleave with the flood's. Interactive jobs keep
their boost above batch jobs. Tags are only ever compared, never bounded:
2^53 of them would take centuries.

Without named users (one local user) the plan's priorities stand, as they
always were: equal jobs advance together.
"""

from __future__ import annotations

from collections.abc import Collection, Iterable
from dataclasses import replace

from .tile_plan import TileSpec

# Above every tag: an interactive tile outranks every batch tile, as in tile_plan.
INTERACTIVE_BOOST = 1 << 53


class FairShare:
    def __init__(self, enabled: bool):
        self.enabled = enabled
        self._clock = 0                  # the largest tag started so far
        self._ends: dict[str, int] = {}  # job id -> the tag after its last tile

    def order(self, job_id: str, interactive: bool, specs: list[TileSpec], owners_jobs: Iterable[str],
              running: Collection[str]) -> list[TileSpec]:
        """`specs` (a job's plan, previews before the tiles that take their
        pixels) with fair priorities; as they are without named users.
        `owners_jobs`: the ids of the owner's other jobs not ended; `running`:
        every job not ended (the ends of the others are forgotten, so that a
        user's cancelled backlog does not push their next job back)."""
        if not self.enabled:
            return specs
        for gone in [j for j in self._ends if j not in running]:
            del self._ends[gone]
        start = max([self._clock, *(self._ends.get(j, 0) for j in owners_jobs)])
        boost = INTERACTIVE_BOOST if interactive else 0
        fair: dict[TileSpec, TileSpec] = {}
        for tag, spec in enumerate(specs, start):
            preview = fair[spec.preview] if spec.preview is not None else None
            fair[spec] = replace(spec, priority=boost - tag, preview=preview)
        self._ends[job_id] = start + len(specs)
        return list(fair.values())

    def started(self, spec: TileSpec, interactive: bool) -> None:
        """A worker started the tile: the clock moves on to its tag."""
        if self.enabled:
            self._clock = max(self._clock, (INTERACTIVE_BOOST if interactive else 0) - spec.priority)
