// The 3D view's two projections, the renderer's two (integrator/camera.h): a
// PerspectiveCamera with the vertical field of view, or an OrthographicCamera
// whose frustum is ortho_height tall (top - bottom over the zoom, which
// OrbitControls changes as one dollies) and as wide as the image's aspect
// makes it, its near plane on the camera's plane where the renderer's
// parallel rays leave from. Either way the canvas has the image's aspect, so
// the view is the frame that renders.
import * as THREE from "three";

/** World units the view spans vertically at the orbit target (at any distance, for an orthographic view). */
export function viewHeight(camera, target) {
  if (camera.isOrthographicCamera) return (camera.top - camera.bottom) / camera.zoom;
  const distance = camera.position.distanceTo(target);
  return 2 * distance * Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2);
}

/** Gives `camera` the aspect (width / height) of the image. */
export function fitAspect(camera, aspect) {
  if (camera.isOrthographicCamera) {
    camera.left = camera.bottom * aspect;
    camera.right = camera.top * aspect;
  } else {
    camera.aspect = aspect;
  }
  camera.updateProjectionMatrix();
}

/** An orthographic camera's frustum `height` world units tall at zoom 1, `aspect` times as wide. */
export function setOrthoHeight(camera, height, aspect) {
  camera.top = height / 2;
  camera.bottom = -height / 2;
  camera.zoom = 1;
  fitAspect(camera, aspect);
}

/** Puts `to` where `from` is, looking the same way. */
export function copyPose(to, from) {
  to.position.copy(from.position);
  to.quaternion.copy(from.quaternion);
  to.up.copy(from.up);
}

/**
 * Where a perspective camera of `fov` degrees stands, on the line from `target`
 * through `from`'s position, for the target's plane to look as large as it does
 * in the orthographic `from`: switching back keeps the framing.
 */
export function perspectivePosition(from, target, fov) {
  const distance = viewHeight(from, target) / (2 * Math.tan(THREE.MathUtils.degToRad(fov) / 2));
  const away = from.position.clone().sub(target);
  if (away.lengthSq() === 0) away.set(0, 0, 1).applyQuaternion(from.quaternion);
  return target.clone().add(away.normalize().multiplyScalar(distance));
}
