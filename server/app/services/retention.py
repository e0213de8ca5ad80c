"""The retention policy (RT_KEEP_JOBS, RT_KEEP_DAYS): which jobs that have
ended go, so that the data folder does not grow forever.

A job is kept while it is among its owner's newest `keep_jobs` jobs (each
user keeps their own N: one user's many jobs never push out another's) or
was made in the last `keep_days` days (either setting 0: that rule keeps nothing by
itself; both 0: every job is kept). Queued and running jobs, pinned ones
(Job.pinned) and every view's reference are always kept.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable

from ..core.config import Settings
from .job_store import ACTIVE_STATES, JobStore
from .references import reference_ids
from .scene_store import SceneStore

DAY_SECONDS = 86400.0
# How often the policy looks again, besides whenever a job ends: the days
# rule lets jobs go as they age.
PERIOD_SECONDS = 3600.0

log = logging.getLogger("rt.retention")


def applies(settings: Settings) -> bool:
    """Whether a policy is set: without one every job is kept."""
    return bool(settings.keep_jobs or settings.keep_days)


def expired(settings: Settings, store: JobStore, scenes: SceneStore, now: float) -> list[str]:
    """The ids of the jobs the policy removes now, oldest last."""
    if not applies(settings):
        return []
    cutoff = now - settings.keep_days * DAY_SECONDS if settings.keep_days else None
    references = reference_ids(scenes)
    gone = []
    ranks: dict[str, int] = {}  # jobs of each owner seen so far, newest first
    for job_id, created_at, state, owner in store.ages():
        rank = ranks[owner] = ranks.get(owner, -1) + 1
        if (settings.keep_jobs and rank < settings.keep_jobs) or (cutoff is not None and created_at >= cutoff):
            continue
        if state in ACTIVE_STATES or job_id in references:
            continue
        job = store.get(job_id)  # its record only now: few jobs get this far
        if job is not None and not job.pinned:
            gone.append(job_id)
    return gone


def policy(settings: Settings) -> str:
    """The policy in words, for the log."""
    rules = ([f"each user's newest {settings.keep_jobs}"] if settings.keep_jobs else []) + \
        ([f"those of the last {settings.keep_days:g} days"] if settings.keep_days else [])
    return "keeping every job" if not rules else "keeping " + " and ".join(rules) + \
        ", pinned ones and references"



async def keep_applying(apply: Callable[[], Awaitable[None]]) -> None:
    """Runs `apply` now and every PERIOD_SECONDS until cancelled."""
    while True:
        try:
            await apply()
        except Exception:  # a bad moment (a disk hiccup) must not end the policy
            log.exception("retention failed; trying again in an hour")
        await asyncio.sleep(PERIOD_SECONDS)
