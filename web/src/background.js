// The background the renderer shows where rays miss (geometry/background.h),
// drawn behind the 3D view so that orbiting shows what the render will: a
// gradient over the height (world y) of each pixel's view direction, from
// `bottom` (straight down) through `horizon` (level) to `top` (straight up).
// Colours are linear RGB, as the renderer's; the shader hands them to three.js's
// output conversion (sRGB on the canvas) like any other linear colour.
import * as THREE from "three";

/**
 * {bottom, horizon, top} (linear RGB arrays) from anything shaped like
 * rt.SceneExtras or rt.RenderSettings: a solid `background` of 3 values, or a
 * `background_gradient` / `backgroundGradient` {bottom, top, horizon?} whose
 * missing horizon is the mean of bottom and top. Null when it gives neither.
 */
export function backgroundOf(source) {
  const solid = source?.background;
  if (solid?.length === 3) return { bottom: [...solid], horizon: [...solid], top: [...solid] };
  const g = source?.background_gradient ?? source?.backgroundGradient;
  if (g?.bottom?.length !== 3 || g?.top?.length !== 3) return null;
  const horizon = g.horizon?.length === 3 ? [...g.horizon] : g.bottom.map((b, i) => (b + g.top[i]) / 2);
  return { bottom: [...g.bottom], horizon, top: [...g.top] };
}

/** The background a model.glb shows: its scene's `extras.rt`, or, while the default rig is on, `extras.rt_default_rig`. */
export function glbBackgrounds(gltfScene) {
  const extras = gltfScene?.userData ?? {};
  return { own: backgroundOf(extras.rt), rig: backgroundOf(extras.rt_default_rig) };
}

/** The colour the gradient gives a unit direction's height y, as the renderer computes it. */
export function backgroundAt(background, y) {
  const t = Math.min(Math.max(y, -1), 1);
  const to = t >= 0 ? background.top : background.bottom;
  return background.horizon.map((h, i) => h + (to[i] - h) * Math.abs(t));
}

// A triangle covering the screen; each corner's view direction is unprojected
// from its NDC (far point minus near point, so an orthographic camera's
// parallel rays come out right too) and turned into world space.
const VERTEX = /* glsl */ `
varying vec3 vDirection;
void main() {
  mat4 unproject = inverse(projectionMatrix);
  vec4 far = unproject * vec4(position.xy, 1.0, 1.0);
  vec4 near = unproject * vec4(position.xy, -1.0, 1.0);
  vec3 view = far.xyz / far.w - near.xyz / near.w;
  vDirection = transpose(mat3(viewMatrix)) * view;
  gl_Position = vec4(position.xy, 1.0, 1.0);
}`;

const FRAGMENT = /* glsl */ `
uniform vec3 bottom;
uniform vec3 horizon;
uniform vec3 top;
varying vec3 vDirection;
void main() {
  float y = clamp(normalize(vDirection).y, -1.0, 1.0);
  gl_FragColor = vec4(y >= 0.0 ? mix(horizon, top, y) : mix(horizon, bottom, -y), 1.0);
  #include <tonemapping_fragment>
  #include <colorspace_fragment>
}`;

/** The gradient as a mesh drawn first, behind everything, never picked. */
export class SkyBackground {
  constructor() {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.Float32BufferAttribute([-1, -1, 0, 3, -1, 0, -1, 3, 0], 3));
    this.material = new THREE.ShaderMaterial({
      vertexShader: VERTEX,
      fragmentShader: FRAGMENT,
      uniforms: { bottom: { value: new THREE.Vector3() }, horizon: { value: new THREE.Vector3() }, top: { value: new THREE.Vector3() } },
      depthTest: false,
      depthWrite: false,
    });
    this.mesh = new THREE.Mesh(geometry, this.material);
    this.mesh.name = "background";
    this.mesh.frustumCulled = false;
    this.mesh.renderOrder = -Infinity;
    this.mesh.raycast = () => {};
    this.value = null;
  }

  /** Shows `background` ({bottom, horizon, top}, linear RGB). */
  set(background) {
    this.value = background;
    for (const key of ["bottom", "horizon", "top"]) this.material.uniforms[key].value.fromArray(background[key]);
  }
}
