// The 3D view's camera as an rt.Camera and back. Three's PerspectiveCamera and
// the renderer's pinhole agree on every term: the eye, the point looked at (the
// orbit target), the up vector, the vertical field of view in degrees, and the
// aspect (the canvas always has the render's width / height, see Viewer.resize).
import { create, schema } from "./proto.js";

const round = (v) => Math.fround(v);

/** rt.Camera of what the 3D view shows now. */
export function viewToCamera(viewer) {
  const { camera, controls } = viewer;
  return create(schema("Camera"), {
    position: camera.position.toArray().map(round),
    target: controls.target.toArray().map(round),
    up: camera.up.toArray().map(round),
    fovY: round(camera.fov),
  });
}

/** Puts the 3D view where an rt.Camera is (absent fov: the schema's default). */
export function cameraToView(viewer, rtCamera, defaultFov) {
  viewer.setView({
    position: rtCamera.position,
    target: rtCamera.target,
    up: rtCamera.up,
    fovY: rtCamera.fovY ?? defaultFov,
  });
}
