// The 3D view: renderer, camera, orbit controls, the scene's model.glb as the
// renderer sees it, and gizmos for its lights and spheres. The canvas always
// has the aspect of the image to render, so the view is the frame that renders.
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { SkyBackground, glbBackgrounds } from "./background.js";
import { instanceSharedMeshes } from "./instancing.js";
import { InteractiveLod } from "./lod.js";
import { copyPose, fitAspect, perspectivePosition, setOrthoHeight, viewHeight } from "./view-projection.js";

const LIGHT_COLOR = 0xffd24a;
const SPHERE_GIZMO_COLOR = 0x5ad1ff;

/** Three great circles of a sphere as line-segment vertex positions. */
function circlePositions(center, radius, segments = 48) {
  const out = [];
  for (let axis = 0; axis < 3; axis++) {
    for (let i = 0; i < segments; i++) {
      for (const k of [i, i + 1]) {
        const a = (k / segments) * Math.PI * 2;
        const p = [Math.cos(a) * radius, Math.sin(a) * radius, 0];
        const v = axis === 0 ? p : axis === 1 ? [p[0], 0, p[1]] : [0, p[0], p[1]];
        out.push(center[0] + v[0], center[1] + v[1], center[2] + v[2]);
      }
    }
  }
  return out;
}

/** Whether WebGL runs on the CPU here. */
function softwareGpu() {
  const gl = document.createElement("canvas").getContext("webgl2");
  if (!gl) return false;
  const info = gl.getExtension("WEBGL_debug_renderer_info");
  const name = info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
  gl.getExtension("WEBGL_lose_context")?.loseContext();
  return /swiftshader|llvmpipe|software/i.test(name);
}

export class Viewer extends EventTarget {
  constructor(container) {
    super();
    this.container = container;
    this.aspect = 4 / 3;
    // Multisampling costs a software GPU (SwiftShader, llvmpipe) more than it shows.
    this.renderer = new THREE.WebGLRenderer({ antialias: !softwareGpu(), preserveDrawingBuffer: false });
    this.pixelRatio = Math.min(window.devicePixelRatio, 2);
    this.renderer.setPixelRatio(this.pixelRatio);
    this.renderer.domElement.setAttribute("aria-label", "3D view of the scene: drag to orbit, right-drag to pan, wheel to zoom");
    this.renderer.domElement.tabIndex = 0;
    container.appendChild(this.renderer.domElement);

    this.scene = new THREE.Scene();
    // What the render shows where rays miss: the scene's background (model.glb),
    // or the settings' (setBackground); dark grey until a scene is shown.
    this.sky = new SkyBackground();
    this.sceneBackgrounds = { own: null, rig: null };
    this.backgroundOverride = null;
    this.scene.add(this.sky.mesh);
    this._showBackground();
    this.camera = new THREE.PerspectiveCamera(45, this.aspect, 0.01, 1000);
    this.camera.position.set(0, 1, 4);
    // this.camera is one of the two; the perspective one keeps the field of view meanwhile.
    this.perspective = this.camera;
    this.orthoCamera = null;
    // No lights of its own: the view is lit by model.glb's KHR_lights_punctual
    // lights, the render's (the default rig when the scene has none), without
    // shadows or reflections.
    this.scene.add(this.camera);

    this.model = new THREE.Group();
    this.gizmos = new THREE.Group();
    this.overlays = new THREE.Group(); // debug rays, BVH boxes
    this.scene.add(this.model, this.gizmos, this.overlays);
    this.loader = new GLTFLoader();
    this.bounds = new THREE.Box3(new THREE.Vector3(-1, -1, -1), new THREE.Vector3(1, 1, 1));

    this._makeControls(new THREE.Vector3(0, 1, 0));
    this.lod = new InteractiveLod(this);
    this.frames = 0;
    this._dirty = true;
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
    this.renderer.setAnimationLoop(() => this._frame());
  }

  _makeControls(up) {
    const target = this.controls ? this.controls.target.clone() : new THREE.Vector3();
    this.controls?.dispose();
    this.camera.up.copy(up);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.target.copy(target);
    this.controls.enableDamping = false;
    this.controls.screenSpacePanning = true;
    this.controls.listenToKeyEvents(this.renderer.domElement);
    this.controls.addEventListener("change", () => {
      this.requestRender();
      this.dispatchEvent(new Event("camerachange"));
    });
    this.controls.addEventListener("end", () => this.dispatchEvent(new Event("orbitend")));
  }

  /** The aspect (width / height) of the image to render: the canvas takes it. */
  setAspect(aspect) {
    if (!(aspect > 0) || aspect === this.aspect) return;
    this.aspect = aspect;
    this.resize();
  }

  resize() {
    const { clientWidth: cw, clientHeight: ch } = this.container;
    if (cw === 0 || ch === 0) return;
    let w = cw;
    let h = Math.round(cw / this.aspect);
    if (h > ch) {
      h = ch;
      w = Math.round(ch * this.aspect);
    }
    this.renderer.setSize(w, h);
    fitAspect(this.camera, this.aspect);
    this.requestRender();
  }

  /** Renders at `share` of the device's pixel ratio (the canvas keeps its size on the page). */
  setResolution(share) {
    const ratio = this.pixelRatio * share;
    if (ratio === this.renderer.getPixelRatio()) return;
    this.renderer.setPixelRatio(ratio);
    this.resize();
  }

  /** Draws the view at the next animation frame (the view only redraws when something changed). */
  requestRender() {
    this._dirty = true;
  }

  _frame() {
    this.lod.tick(performance.now());
    if (!this._dirty) return;
    this._dirty = false;
    this.frames++;
    this.renderer.render(this.scene, this.camera);
    this.lod.frame(performance.now());
  }

  /**
   * Sets the view from position/target/up arrays and a vertical fov in degrees;
   * `orthographic`: parallel rays, the view `orthoHeight` world units tall.
   */
  setView({ position, target, up, fovY, orthographic = false, orthoHeight }) {
    this._useCamera(orthographic);
    const upVector = new THREE.Vector3(...(up && up.length === 3 ? up : [0, 1, 0])).normalize();
    if (!upVector.equals(this.camera.up)) this._makeControls(upVector);
    this.camera.position.set(...position);
    this.controls.target.set(...target);
    if (fovY > 0) this.perspective.fov = fovY;
    this.perspective.updateProjectionMatrix();
    if (orthographic) setOrthoHeight(this.camera, orthoHeight > 0 ? orthoHeight : 1, this.aspect);
    this._fitClipPlanes();
    this.controls.update();
    this.requestRender();
    this.dispatchEvent(new Event("camerachange"));
  }

  setFov(fovY) {
    this.perspective.fov = fovY;
    this.perspective.updateProjectionMatrix();
    this.requestRender();
    this.dispatchEvent(new Event("camerachange"));
  }

  _fitClipPlanes() {
    const size = this.bounds.getSize(new THREE.Vector3()).length() || 1;
    const distance = this.camera.position.distanceTo(this.bounds.getCenter(new THREE.Vector3()));
    // An orthographic view sees from its own plane on, as the renderer's parallel rays do.
    this.camera.near = this.orthographic ? 0 : Math.max(size * 1e-4, (distance - size * 2) * 0.5, 1e-4);
    this.camera.far = distance + size * 4;
    this.camera.updateProjectionMatrix();
    this.controls.minDistance = size * 1e-3;
    this.controls.maxDistance = size * 50;
  }

  get orthographic() {
    return this.camera.isOrthographicCamera === true;
  }

  /** The perspective view's vertical field of view in degrees (kept while the view is orthographic). */
  get fov() {
    return this.perspective.fov;
  }

  /** World units the view spans vertically at the orbit target. */
  get viewHeight() {
    return viewHeight(this.camera, this.controls.target);
  }

  /**
   * Switches the view to orthographic, `height` world units tall (by default
   * what it shows at the orbit target now), or back to perspective, standing
   * where the target's plane looks as large as it did.
   */
  setProjection(orthographic, height = null) {
    const from = this.camera;
    const shown = this.viewHeight;
    const target = this.controls.target.clone();
    this._useCamera(orthographic);
    if (orthographic) setOrthoHeight(this.camera, height ?? shown, this.aspect);
    else if (from.isOrthographicCamera) this.camera.position.copy(perspectivePosition(from, target, this.fov));
    this._fitClipPlanes();
    this.controls.update();
    this.requestRender();
    this.dispatchEvent(new Event("camerachange"));
  }

  // Makes the perspective or the orthographic camera the view's, in the other's pose.
  _useCamera(orthographic) {
    if (orthographic === this.orthographic) return;
    const from = this.camera;
    this.orthoCamera ??= new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1000);
    const to = orthographic ? this.orthoCamera : this.perspective;
    copyPose(to, from);
    for (const child of [...from.children]) to.add(child);
    this.scene.remove(from);
    this.scene.add(to);
    this.camera = to;
    fitAspect(to, this.aspect);
    this._makeControls(to.up.clone());
  }

  /** The scene's diagonal: sizes of gizmos and normals follow it. */
  get sceneSize() {
    return this.bounds.getSize(new THREE.Vector3()).length() || 1;
  }

  clearScene() {
    this.lod.clear();
    this.sceneBackgrounds = { own: null, rig: null };
    this._showBackground();
    for (const group of [this.model, this.gizmos]) {
      for (const child of [...group.children]) {
        group.remove(child);
        child.traverse((o) => {
          o.geometry?.dispose();
          for (const m of [].concat(o.material ?? [])) m.dispose();
        });
      }
    }
    this.requestRender();
  }

  /**
   * Loads the scene's model.glb and draws gizmos for `info.lights` and the
   * spheres the GLB marks (extras.rt.sphere). Resolves once it is shown.
   */
  async loadScene(url, info) {
    const gltf = await this.loader.loadAsync(url);
    this.clearScene();
    const spheres = [];
    gltf.scene.traverse((object) => {
      const sphere = object.userData?.rt?.sphere;
      if (sphere) spheres.push(sphere);
      if (object.isMesh) {
        for (const m of [].concat(object.material)) m.side = THREE.DoubleSide;
      }
    });
    this.instancedMeshes = instanceSharedMeshes(gltf.scene);
    this.model.add(gltf.scene);
    this.sceneBackgrounds = glbBackgrounds(gltf.scene);
    this.showLightRig(this.rigOn ?? true);
    this.bounds.set(new THREE.Vector3(...info.boundsMin), new THREE.Vector3(...info.boundsMax));
    if (this.bounds.isEmpty()) this.bounds.setFromObject(gltf.scene);
    this._addGizmos(info.lights, spheres);
    this._fitClipPlanes();
    this.lod.prepare();
    this.requestRender();
    return gltf;
  }

  /** Shows or hides the default rig's lights (model.glb marks them extras.rt.default_rig). */
  showLightRig(on) {
    this.rigOn = on;
    this.model.traverse((o) => {
      if (o.isLight && o.userData?.rt?.default_rig) o.visible = on;
    });
    this._showBackground();
    this.requestRender();
  }

  /** The scene's own background as the render shows it now ({bottom, horizon, top}, linear), or null. */
  get sceneBackground() {
    const { own, rig } = this.sceneBackgrounds;
    return ((this.rigOn ?? true) && rig) || own;
  }

  /** Draws `background` ({bottom, horizon, top}, linear RGB) instead of the scene's; null: the scene's again. */
  setBackground(background) {
    this.backgroundOverride = background;
    this._showBackground();
  }

  _showBackground() {
    const dark = new THREE.Color(0x15171c); // linear, as three.js's working colour space
    const fallback = { bottom: dark.toArray(), horizon: dark.toArray(), top: dark.toArray() };
    this.sky.set(this.backgroundOverride ?? this.sceneBackground ?? fallback);
    this.dispatchEvent(new CustomEvent("scenebackground", { detail: this.sceneBackground }));
    this.requestRender();
  }

  _addGizmos(lights, spheres) {
    const size = this.sceneSize;
    const markerGeometry = new THREE.OctahedronGeometry(size * 0.012);
    for (const light of lights) {
      const marker = new THREE.Mesh(markerGeometry, new THREE.MeshBasicMaterial({ color: LIGHT_COLOR }));
      marker.position.set(...light.position);
      marker.name = "light gizmo";
      this.gizmos.add(marker);
      if (light.radius > 0) {
        const ring = new THREE.BufferGeometry();
        ring.setAttribute("position", new THREE.Float32BufferAttribute(circlePositions(light.position, light.radius), 3));
        this.gizmos.add(new THREE.LineSegments(ring, new THREE.LineBasicMaterial({ color: LIGHT_COLOR })));
      }
    }
    if (spheres.length) {
      const positions = spheres.flatMap((s) => circlePositions(s.center, s.radius * 1.002));
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute("position", new THREE.Float32BufferAttribute(positions, 3));
      const lines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: SPHERE_GIZMO_COLOR }));
      lines.name = "sphere gizmos";
      this.gizmos.add(lines);
    }
  }

  /** Normalized device coordinates of a pointer event over the canvas. */
  ndc(event) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    return new THREE.Vector2(((event.clientX - rect.left) / rect.width) * 2 - 1,
      -((event.clientY - rect.top) / rect.height) * 2 + 1);
  }
}
