// The 3D view's camera as an rt.Camera and back. Three's cameras and the
// renderer's agree on every term: the eye, the point looked at (the orbit
// target), the up vector, the vertical field of view in degrees or, for an
// orthographic view, the height it spans in world units (ortho_height), and
// the aspect (the canvas always has the render's width / height, see
// Viewer.resize).
import { create, enumOf, schema } from "./proto.js";

const round = (v) => Math.fround(v);
const ORTHOGRAPHIC = () => enumOf("Projection").values.find((v) => v.name === "ORTHOGRAPHIC").number;

/** rt.Camera of what the 3D view shows now. */
export function viewToCamera(viewer) {
  const { camera, controls } = viewer;
  const ortho = viewer.orthographic ? { projection: ORTHOGRAPHIC(), orthoHeight: round(viewer.viewHeight) } : {};
  return create(schema("Camera"), {
    position: camera.position.toArray().map(round),
    target: controls.target.toArray().map(round),
    up: camera.up.toArray().map(round),
    fovY: round(viewer.fov),
    ...ortho,
  });
}

/** Puts the 3D view where an rt.Camera is (absent fov: the schema's default). */
export function cameraToView(viewer, rtCamera, defaultFov) {
  viewer.setView({
    position: rtCamera.position,
    target: rtCamera.target,
    up: rtCamera.up,
    fovY: rtCamera.fovY ?? defaultFov,
    orthographic: rtCamera.projection === ORTHOGRAPHIC(),
    orthoHeight: rtCamera.orthoHeight,
  });
}
