"""Loaded scenes, one per process, keyed by the upload's content hash.

Loading a scene and building its BVH costs far more than rendering a tile, so
every worker keeps the scenes it has loaded, within a budget of their
memory_bytes (what rtcore really stores: a mesh that many nodes share counts
once; Settings.scene_cache_bytes). Beyond it, or when the machine's memory runs
short, the least recently used scenes go first; a scene in use stays alive
through its callers' references even after eviction.
"""

from __future__ import annotations

import atexit
import threading
from collections import OrderedDict
from collections.abc import Callable
from pathlib import Path

import psutil
import rtcore

from ..core.config import load_settings

# Keep at least this share of the machine's memory free; evict beyond it.
MIN_AVAILABLE_FRACTION = 0.15
MAX_SCENES = 16

_lock = threading.Lock()
_scenes: OrderedDict[str, rtcore.Scene] = OrderedDict()
_loading: dict[str, threading.Lock] = {}
# Dropped as the interpreter exits, before rtcore's own teardown: otherwise
# nanobind reports the scenes still held here as leaked.
atexit.register(_scenes.clear)


def _memory_short() -> bool:
    memory = psutil.virtual_memory()
    return memory.available < MIN_AVAILABLE_FRACTION * memory.total


def budget_bytes() -> int:
    return load_settings().scene_cache_bytes or psutil.virtual_memory().total // 2


def cached_bytes() -> int:
    with _lock:
        return sum(scene.memory_bytes for scene in _scenes.values())


def _evict_while_needed(keep: str) -> None:
    budget = budget_bytes()
    with _lock:
        while _scenes and (len(_scenes) > MAX_SCENES or _memory_short()
                           or sum(scene.memory_bytes for scene in _scenes.values()) > budget):
            oldest = next(iter(_scenes))
            if oldest == keep:
                if len(_scenes) == 1:
                    return
                _scenes.move_to_end(oldest)
                continue
            del _scenes[oldest]


def get_scene(content_hash: str, source: str | Path | Callable[[], rtcore.Scene]) -> rtcore.Scene:
    """The scene whose upload hashed to `content_hash`, loaded from `source`
    (its path, or a function that answers it) once per process even when many
    threads ask at the same time."""
    with _lock:
        scene = _scenes.get(content_hash)
        if scene is not None:
            _scenes.move_to_end(content_hash)
            return scene
        loading = _loading.setdefault(content_hash, threading.Lock())
    with loading:
        with _lock:
            scene = _scenes.get(content_hash)
        if scene is None:
            scene = source() if callable(source) else rtcore.Scene.load(str(source))
            with _lock:
                _scenes[content_hash] = scene
                _loading.pop(content_hash, None)
            _evict_while_needed(keep=content_hash)
    return scene


def forget(content_hash: str) -> None:
    with _lock:
        _scenes.pop(content_hash, None)
