"""services/debugger.py: the debugger's views run the renderer in a worker
thread, and refuse bad requests with Invalid naming the problem."""

import asyncio
import json
import threading

import pytest
import rtcore
from rt import debug_pb2, job_pb2

from app.services import debugger
from app.services.errors import Invalid


@pytest.fixture(scope="module")
def cornell(scenes_dir):
    return rtcore.Scene.load(str(scenes_dir / "cornell.obj"))


class Recording:
    """A stored scene whose renderer notes the thread each call runs on; its
    requests are completed by a real scene."""

    def __init__(self, scene=None):
        self.info = job_pb2.SceneInfo(id="s")
        self.scene = scene
        self.threads: dict[str, int] = {}

    def complete(self, type_name, data):
        self.threads["complete"] = threading.get_ident()
        return self.scene.complete(type_name, data)

    def load(self):
        self.threads["load"] = threading.get_ident()
        return self

    def bvh_boxes(self, level, tree):
        self.threads["bvh_boxes"] = threading.get_ident()
        if tree not in ("top", "0"):
            raise ValueError(f"tree: '{tree}' is not top, world or an instance number below 1")
        return debug_pb2.BvhBoxes(level=level, total_levels=3).SerializeToString()

    def debug_path(self, camera, settings, x, y):
        self.threads["debug_path"] = threading.get_ident()
        return debug_pb2.DebugPath(pixel_x=x, pixel_y=y).SerializeToString()


def on_a_loop(coroutine_function, *args):
    """Runs it on an event loop; answers its result and the loop's thread."""
    async def run():
        return await coroutine_function(*args), threading.get_ident()
    return asyncio.run(run())


def test_bvh_boxes_run_off_the_event_loop():
    stored = Recording()
    boxes, loop_thread = on_a_loop(debugger.bvh_boxes, stored, 1, False)
    assert (boxes.level, boxes.total_levels) == (1, 3)
    assert stored.threads["bvh_boxes"] != loop_thread and stored.threads["load"] != loop_thread


def test_all_leaves_ask_the_renderer_for_level_minus_one():
    boxes, _ = on_a_loop(debugger.bvh_boxes, Recording(), 7, True)
    assert boxes.level == -1


def test_a_level_past_the_deepest_is_invalid():
    with pytest.raises(Invalid, match="level: 3 is past the deepest level 2"):
        on_a_loop(debugger.bvh_boxes, Recording(), 3, False)


def test_a_tree_the_renderer_refuses_is_invalid():
    with pytest.raises(Invalid, match="tree: 'world' is not top"):
        on_a_loop(debugger.bvh_boxes, Recording(), 0, False, "world")
    boxes, _ = on_a_loop(debugger.bvh_boxes, Recording(), 0, False, "0")
    assert boxes.total_levels == 3


def test_debug_ray_traces_off_the_event_loop_with_the_scenes_camera(cornell):
    stored = Recording(cornell)
    body = json.dumps({"settings": {"width": 8, "height": 6}, "pixel": [7, 5]}).encode()
    path, loop_thread = on_a_loop(debugger.debug_ray, stored, body)
    assert (path.pixel_x, path.pixel_y) == (7, 5)
    assert stored.threads["debug_path"] != loop_thread and stored.threads["complete"] != loop_thread


@pytest.mark.parametrize("body, words", [
    (b"", "empty body"),
    (b'{"pixel": [1]}', "pixel: needs 2 values"),
    (b'{"settings": {"width": 8, "height": 6}, "pixel": [8, 0]}', "pixel: (8, 0) is outside the 8x6 image"),
])
def test_debug_ray_refuses_bad_requests_as_invalid(cornell, body, words):
    with pytest.raises(Invalid) as refused:
        on_a_loop(debugger.debug_ray, Recording(cornell), body)
    assert words in str(refused.value)


def test_a_request_without_settings_gets_the_schemas_defaults_and_the_scenes_camera(cornell):
    request = debugger.read_request(Recording(cornell), b'{"pixel": [0, 0]}')
    assert request.HasField("settings") and request.settings.width == 640
    assert request.camera.SerializeToString() == cornell.default_camera
