"""The pixel debugger's views of a stored scene: every ray traced for one pixel
(rtcore's debug_path, the render's own trace) and the BVH boxes of one level.
The renderer runs in a worker thread, never on the event loop."""

from __future__ import annotations

import asyncio

from rt import debug_pb2, job_pb2

from ..core.proto import normalize
from .errors import Invalid
from .scene_store import StoredScene


def read_request(stored: StoredScene, body: bytes) -> job_pb2.DebugRayRequest:
    """A JSON rt.DebugRayRequest completed for the scene and checked
    (core.proto.normalize); blocking. Raises Invalid naming the field."""
    try:
        request = normalize(job_pb2.DebugRayRequest, body, lambda _: stored.load())
    except ValueError as e:
        raise Invalid(str(e)) from None
    x, y = request.pixel
    if x >= request.settings.width or y >= request.settings.height:
        raise Invalid(f"pixel: ({x}, {y}) is outside the {request.settings.width}x{request.settings.height} image")
    return request


def _debug_path(stored: StoredScene, body: bytes) -> debug_pb2.DebugPath:
    request = read_request(stored, body)
    data = stored.load().debug_path(request.camera.SerializeToString(), request.settings.SerializeToString(),
                                    *request.pixel)
    return debug_pb2.DebugPath.FromString(data)


async def debug_ray(stored: StoredScene, body: bytes) -> debug_pb2.DebugPath:
    """Every ray traced for the pixel a JSON rt.DebugRayRequest names, through
    its camera or else the scene's default one. Raises Invalid naming the problem."""
    return await asyncio.to_thread(_debug_path, stored, body)


def _bvh_boxes(stored: StoredScene, level: int, tree: str) -> debug_pb2.BvhBoxes:
    try:
        return debug_pb2.BvhBoxes.FromString(stored.load().bvh_boxes(level, tree))
    except ValueError as e:
        raise Invalid(str(e)) from None


async def bvh_boxes(stored: StoredScene, level: int, leaves: bool, tree: str = "top") -> debug_pb2.BvhBoxes:
    """The boxes of one level of a tree of the wide BVH the renderer traverses
    (0 is the root; a node's up to node_width children, nodes and leaves, one
    level down), or every leaf box. `tree` is "top", "world" or an instance
    number (rtcore's Scene.bvh_boxes). Raises Invalid for a tree the scene
    lacks or a level past the deepest."""
    boxes = await asyncio.to_thread(_bvh_boxes, stored, -1 if leaves else level, tree)
    if not leaves and level >= boxes.total_levels:
        raise Invalid(f"level: {level} is past the deepest level {boxes.total_levels - 1}")
    return boxes
