"""The workers' scene cache: scenes are counted by what rtcore stores (a mesh
many nodes share once), and the least recently used go once the cache is over
its byte budget (RT_SCENE_CACHE_MB)."""
import pytest
from app.services import scene_cache

from instanced_scene import instanced_gltf

NODES = 2000


@pytest.fixture
def files(tmp_path):
    paths = {}
    for name, copies in (("shared", False), ("copies", True)):
        paths[name] = tmp_path / f"{name}.gltf"
        paths[name].write_text(instanced_gltf(NODES, copies=copies))
    yield paths
    for name in paths:
        scene_cache.forget(f"test-{name}")


def test_a_shared_mesh_counts_once(files):
    shared = scene_cache.get_scene("test-shared", files["shared"])
    copies = scene_cache.get_scene("test-copies", files["copies"])
    assert shared.triangle_count == copies.triangle_count == 8 * NODES
    # Each instance keeps its transforms (to the world and back, and where it
    # is at shutter close), which weigh about a third of an 8-triangle copy.
    assert shared.memory_bytes * 2.5 < copies.memory_bytes, (shared.memory_bytes, copies.memory_bytes)


def test_scenes_over_the_byte_budget_are_evicted_oldest_first(files, monkeypatch):
    monkeypatch.setenv("RT_SCENE_CACHE_MB", "1")
    copies = scene_cache.get_scene("test-copies", files["copies"])
    assert copies.memory_bytes > scene_cache.budget_bytes(), "the sizes this test needs"
    assert scene_cache.get_scene("test-copies", files["copies"]) is copies, "the scene asked for stays, even alone over"
    shared = scene_cache.get_scene("test-shared", files["shared"])
    assert shared.memory_bytes < scene_cache.budget_bytes()
    assert scene_cache.cached_bytes() <= scene_cache.budget_bytes()
    assert scene_cache.get_scene("test-shared", files["shared"]) is shared
    assert scene_cache.get_scene("test-copies", files["copies"]) is not copies, "evicted, so loaded anew"
