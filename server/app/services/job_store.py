"""Job records in SQLite, each the serialized rt.Job, so a restart loses none.

The owner (Job.owner) is a column too, so that a user's page of jobs, their
count and the retention policy's per-user ranks are read without decoding
every record; databases made before it get the column, empty (the one local
user's), when opened.

Each thread keeps its own connection (sqlite3 connections must stay in the
thread that made them); opening one per call cost more than the write itself,
and the event loop saves every change of a running job's state.
"""

from __future__ import annotations

import sqlite3
import threading
from pathlib import Path

from rt import job_pb2

_SCHEMA = """
CREATE TABLE IF NOT EXISTS jobs (
    id TEXT PRIMARY KEY,
    created_at REAL NOT NULL,
    scene_id TEXT NOT NULL,
    state INTEGER NOT NULL,
    record BLOB NOT NULL
);
CREATE INDEX IF NOT EXISTS jobs_by_time ON jobs (created_at DESC);
"""
_OWNER = """
ALTER TABLE jobs ADD COLUMN owner TEXT NOT NULL DEFAULT '';
"""
_OWNER_INDEX = "CREATE INDEX IF NOT EXISTS jobs_by_owner ON jobs (owner, created_at DESC);"

ACTIVE_STATES = (job_pb2.QUEUED, job_pb2.RUNNING)


class JobStore:
    def __init__(self, database: Path):
        self._database = database
        self._local = threading.local()
        database.parent.mkdir(parents=True, exist_ok=True)
        with self._db() as db:
            db.executescript(_SCHEMA)
            if "owner" not in {row[1] for row in db.execute("PRAGMA table_info(jobs)")}:
                db.executescript(_OWNER)
            db.execute(_OWNER_INDEX)

    def _db(self) -> sqlite3.Connection:
        db = getattr(self._local, "db", None)
        if db is None:
            db = self._local.db = self._connect()
        return db

    def _connect(self) -> sqlite3.Connection:
        db = sqlite3.connect(self._database, timeout=30)
        db.execute("PRAGMA journal_mode=WAL")
        # With WAL, NORMAL keeps the database consistent across a crash and
        # spares the event loop an fsync per saved change of state.
        db.execute("PRAGMA synchronous=NORMAL")
        return db

    def save(self, job: job_pb2.Job) -> None:
        with self._db() as db:
            db.execute(
                "INSERT INTO jobs (id, created_at, scene_id, state, record, owner) VALUES (?, ?, ?, ?, ?, ?) "
                "ON CONFLICT(id) DO UPDATE SET state = excluded.state, record = excluded.record",
                (job.id, job.created_at, job.request.scene_id, job.state, job.SerializeToString(), job.owner))

    def get(self, job_id: str) -> job_pb2.Job | None:
        with self._db() as db:
            row = db.execute("SELECT record FROM jobs WHERE id = ?", (job_id,)).fetchone()
        return job_pb2.Job.FromString(row[0]) if row else None

    def page(self, offset: int, limit: int, owner: str) -> tuple[list[job_pb2.Job], int]:
        """The owner's jobs, newest first; and how many they have."""
        with self._db() as db:
            total = db.execute("SELECT COUNT(*) FROM jobs WHERE owner = ?", (owner,)).fetchone()[0]
            rows = db.execute("SELECT record FROM jobs WHERE owner = ? ORDER BY created_at DESC, id LIMIT ? OFFSET ?",
                              (owner, limit, offset)).fetchall()
        return [job_pb2.Job.FromString(r[0]) for r in rows], total

    def ids(self, owner: str) -> list[str]:
        """The ids of the owner's jobs."""
        with self._db() as db:
            return [r[0] for r in db.execute("SELECT id FROM jobs WHERE owner = ?", (owner,))]

    def ages(self) -> list[tuple[str, float, int, str]]:
        """(id, created_at, state, owner) of every job, newest first, without reading the records."""
        with self._db() as db:
            return db.execute("SELECT id, created_at, state, owner FROM jobs ORDER BY created_at DESC, id").fetchall()

    def delete(self, job_id: str) -> None:
        with self._db() as db:
            db.execute("DELETE FROM jobs WHERE id = ?", (job_id,))

    def active(self) -> list[job_pb2.Job]:
        """Jobs that were queued or running, oldest first."""
        with self._db() as db:
            rows = db.execute(
                f"SELECT record FROM jobs WHERE state IN ({','.join('?' * len(ACTIVE_STATES))}) "
                "ORDER BY created_at", ACTIVE_STATES).fetchall()
        return [job_pb2.Job.FromString(r[0]) for r in rows]
