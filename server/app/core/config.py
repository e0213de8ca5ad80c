"""Settings of the job service, read once from the environment."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from .users import User, load_users

REPO_ROOT = Path(__file__).resolve().parents[3]


def _names(name: str) -> tuple[str, ...]:
    """A comma-separated list from the environment, without blanks."""
    return tuple(part.strip() for part in os.environ.get(name, "").split(",") if part.strip())


def _number(name: str, default, kind: type, minimum=None):
    """An int or float setting; SystemExit naming it when it is not one, or below `minimum` (NaN included)."""
    value = os.environ.get(name)
    if value is None or value == "":
        return default
    what = "an integer" if kind is int else "a number"
    try:
        number = kind(value)
    except ValueError:
        raise SystemExit(f"{name}={value!r}: expected {what}") from None
    if minimum is not None and not number >= minimum:
        raise SystemExit(f"{name}={value!r}: expected {what} of at least {minimum}")
    return number


def _int(name: str, default: int, minimum: int | None = None) -> int:
    return _number(name, default, int, minimum)


@dataclass(frozen=True)
class Settings:
    host: str = field(default_factory=lambda: os.environ.get("HOST", "127.0.0.1"))
    port: int = field(default_factory=lambda: _int("PORT", 8000))
    # Scenes, job records (SQLite) and finished images live here.
    data_dir: Path = field(default_factory=lambda: Path(os.environ.get("RT_DATA_DIR", REPO_ROOT / "data")).resolve())
    # A Dask scheduler address (tcp://host:8786); empty: an embedded local cluster.
    scheduler: str = field(default_factory=lambda: os.environ.get("RT_SCHEDULER", ""))
    # Where workers that do not see the data folder fetch scenes from
    # (services/data_access.py); empty: the bound address, or this machine's
    # name when bound to every interface.
    server_url: str = field(default_factory=lambda: os.environ.get("RT_SERVER_URL", "").strip())
    # The embedded cluster: worker threads run in the server process and share
    # its scene cache; rendering releases the GIL.
    embedded_threads: int = field(default_factory=lambda: _int("RT_THREADS", os.cpu_count() or 1))
    # The built viewer (web/dist), served at /.
    web_dir: Path = field(default_factory=lambda: Path(os.environ.get("RT_WEB_DIR", REPO_ROOT / "web" / "dist")))
    # Host names the server answers besides loopback ones and its bound address
    # (core/local_access.py), and origins besides its own whose pages may
    # change things (uploads, jobs) or open the tile stream.
    allowed_hosts: tuple[str, ...] = field(default_factory=lambda: tuple(h.lower() for h in _names("RT_ALLOWED_HOSTS")))
    allowed_origins: tuple[str, ...] = field(default_factory=lambda: tuple(o.rstrip("/") for o in
                                                                           _names("RT_ALLOWED_ORIGINS")))
    # When set, every /api route and the tile WebSocket need it as a bearer token.
    api_token: str = field(default_factory=lambda: os.environ.get("RT_API_TOKEN", ""))
    # Named users (core/users.py: RT_USERS, RT_USERS_FILE), each with a token:
    # each sees and deletes only their own scenes and jobs, and their tiles take
    # turns with other users' (services/fair_share.py). Empty: one local user.
    users: tuple[User, ...] = field(default_factory=load_users)
    # Per-user quotas, 0 for none: bytes on disk (scenes and job files; an
    # upload or a job past it answers 413), and jobs queued or running (429).
    quota_bytes: int = field(default_factory=lambda: _int("RT_QUOTA_MB", 0, minimum=0) << 20)
    quota_queued_jobs: int = field(default_factory=lambda: _int("RT_QUOTA_QUEUED_JOBS", 0, minimum=0))
    # Sample scenes (make samples) added to the store at start-up when missing.
    samples_dir: Path | None = field(default_factory=lambda: Path(os.environ["RT_SAMPLES_DIR"])
                                     if os.environ.get("RT_SAMPLES_DIR") else None)
    # Upload limits.
    max_upload_bytes: int = field(default_factory=lambda: _int("RT_MAX_UPLOAD_MB", 512) << 20)
    max_unpacked_bytes: int = field(default_factory=lambda: _int("RT_MAX_UNPACKED_MB", 2048) << 20)
    max_upload_files: int = field(default_factory=lambda: _int("RT_MAX_UPLOAD_FILES", 2000))
    # Pixels of one job (the schema caps width and height separately).
    max_job_pixels: int = field(default_factory=lambda: _int("RT_MAX_JOB_PIXELS", 64 << 20))
    # Finished tile streams kept in memory for late viewers; older jobs are
    # streamed from their image on disk.
    kept_streams: int = field(default_factory=lambda: _int("RT_KEPT_STREAMS", 8))
    # The retention policy (services/retention.py): jobs that have ended are
    # removed, with their files, unless among their owner's newest RT_KEEP_JOBS
    # or made in the last RT_KEEP_DAYS days; 0 turns a rule off, both 0 keep all.
    keep_jobs: int = field(default_factory=lambda: _int("RT_KEEP_JOBS", 0, minimum=0))
    keep_days: float = field(default_factory=lambda: _number("RT_KEEP_DAYS", 0.0, float, minimum=0))
    # Loaded scenes a process keeps (their memory_bytes summed, BVHs included);
    # 0: half of the machine's memory. Read by each worker from its environment.
    scene_cache_bytes: int = field(default_factory=lambda: _int("RT_SCENE_CACHE_MB", 0) << 20)

    @property
    def scenes_dir(self) -> Path:
        return self.data_dir / "scenes"

    @property
    def jobs_dir(self) -> Path:
        return self.data_dir / "jobs"

    @property
    def database(self) -> Path:
        return self.data_dir / "jobs.sqlite"


def load_settings() -> Settings:
    return Settings()
