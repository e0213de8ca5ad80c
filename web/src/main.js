// The viewer's entry: builds the panels and wires them together. Scenes load
// into the 3D view; "Render this view" submits a job with the view's camera;
// /jobs/<id> follows a job's tiles and record; clicking the image traces a pixel.
import { getScene, health, modelUrl, submitJob } from "./api.js";
import { cameraToView, viewToCamera } from "./camera-sync.js";
import { DebugPanel } from "./debug-panel.js";
import { ImageLayers } from "./heatmap.js";
import { ImageWorkspace } from "./image-workspace.js";
import { isFinal, JobFollower } from "./job-follower.js";
import { JobPanel, stateOf } from "./job-panel.js";
import { ProjectionControl } from "./projection-control.js";
import { ReferencePanel } from "./reference-panel.js";
import { Router } from "./router.js";
import { ScenesPanel } from "./scenes-panel.js";
import { SettingsPanel } from "./settings-panel.js";
import { ShutterPose } from "./shutter-pose.js";
import { ImageOverlay, RunningTiles } from "./tile-outlines.js";
import { TileView } from "./tiles.js";
import { UserBadge } from "./user-badge.js";
import { ViewSwitch } from "./view-switch.js";
import { Viewer } from "./viewer.js";
import { Wipe } from "./wipe.js";
import { formatBytes } from "./format.js";

const $ = (id) => document.getElementById(id);

const viewer = new Viewer($("viewport"));
const settings = new SettingsPanel($("render-form"));
const scenes = new ScenesPanel(document);
const jobPanel = new JobPanel(document);
const tiles = new TileView($("image-canvas"));
const follower = new JobFollower(tiles);
const overlay = new ImageOverlay($("image-overlay"));
const layers = new ImageLayers($("layer-buttons"), $("layer-image"), $("heat-legend"));
const debug = new DebugPanel(viewer, tiles, overlay);
const image = new ImageWorkspace(tiles, debug);
const views = new ViewSwitch(document);
const reference = new ReferencePanel();
reference.addEventListener("open", (e) => router.go(e.detail));
reference.addEventListener("plot", (e) => jobPanel.showErrors(e.detail));
reference.addEventListener("scene", (e) => { if (state.scene?.id === e.detail.id) state.scene = e.detail; });
const wipe = new Wipe(image.view, viewer.renderer.domElement, $("wipe-handle"));
views.addEventListener("change", (e) => {
  // The wipe compares the render with the 3D view from the job's own camera.
  if (e.detail === "wipe" && state.job) cameraToView(viewer, state.job.request.camera, settings.defaultFov);
  wipe.enable(e.detail === "wipe");
});
const router = new Router();
const cameraSelect = $("scene-camera");
const shutter = new ShutterPose(document, viewer);
const user = new UserBadge(document);

const state = { scene: null, job: null, running: null, sceneLoad: null };

function viewportStatus(text) {
  $("viewport-status").textContent = text;
  $("viewport-status").hidden = !text;
}

// --- the 3D view and the render settings ------------------------------------

viewer.setAspect(settings.aspect);
settings.addEventListener("aspect", (e) => viewer.setAspect(e.detail));
settings.addEventListener("fov", (e) => viewer.setFov(e.detail));
settings.addEventListener("lightRig", (e) => viewer.showLightRig(e.detail));
// The view draws the background the job will get; the panel's pickers start at the scene's.
settings.addEventListener("background", (e) => viewer.setBackground(e.detail));
viewer.addEventListener("scenebackground", (e) => settings.background.setSceneBackground(e.detail));
viewer.addEventListener("camerachange", () => settings.showFov(viewer.fov));
viewer.renderer.domElement.addEventListener("pointerdown", () => { cameraSelect.value = ""; });
viewer.renderer.domElement.addEventListener("wheel", () => { cameraSelect.value = ""; }, { passive: true });
settings.showFov(viewer.fov);
// Switching the projection leaves the scene camera, as orbiting does.
const projection = new ProjectionControl(document, viewer);
projection.addEventListener("change", () => { cameraSelect.value = ""; });

function fillCameras(info) {
  const options = [["", "Free view (orbit)"], ["default", "Default camera (whole scene)"],
    ...info.cameras.map((c, i) => [`camera-${i}`, `Scene camera: ${c.name || `#${i + 1}`}`])];
  cameraSelect.replaceChildren(...options.map(([value, label]) => new Option(label, value)));
}

cameraSelect.addEventListener("change", () => {
  const info = state.scene;
  if (!info || !cameraSelect.value) return;
  const value = cameraSelect.value;
  const camera = value === "default" ? info.defaultCamera : info.cameras[Number(value.split("-")[1])]?.camera;
  if (camera) {
    cameraToView(viewer, camera, settings.defaultFov);
    shutter.set(camera.shutterClose ?? null);
  }
  cameraSelect.value = value;
});

/** Shows a scene in the 3D view; `camera`: where to look from (default: the scene's). */
async function selectScene(id, camera = null) {
  if (state.scene?.id === id) {
    if (camera) {
      cameraToView(viewer, camera, settings.defaultFov);
      cameraSelect.value = "";
    }
    return state.scene;
  }
  viewportStatus("Loading the scene…");
  let info;
  try {
    info = await getScene(id);
    state.scene = info;
    scenes.setSelected(id);
    $("scene-title").textContent = `${info.name} · ${info.triangleCount.toLocaleString()} triangles`;
    fillCameras(info);
    shutter.set(null);
    debug.setScene(info);
    localStorage.setItem("rt.scene", id);
    const load = viewer.loadScene(modelUrl(id), info);
    state.sceneLoad = load;
    cameraToView(viewer, camera ?? info.defaultCamera, settings.defaultFov);
    cameraSelect.value = camera ? "" : "default";
    await load;
    viewportStatus("");
  } catch (e) {
    viewportStatus(`The scene could not be shown: ${e.message}`);
  }
  return info;
}

scenes.addEventListener("select", (e) => {
  selectScene(e.detail);
  user.refresh(); // after an upload, its bytes
});
scenes.addEventListener("deleted", (e) => {
  user.refresh();
  if (state.scene?.id !== e.detail) return;
  state.scene = null;
  viewer.clearScene();
  debug.setScene(null);
  $("scene-title").textContent = "No scene";
  if (scenes.scenes.length) selectScene(scenes.scenes[0].id);
});

// A converged render of the view, the one its other jobs are measured
// against: many samples, adaptive, behind the interactive jobs.
const REFERENCE_SETTINGS = { samplesPerPixel: 1024, adaptiveThreshold: 0.01 };

/** Submits the view as a job (`reference`: the view's reference render) and opens it. */
async function submitView(reference, button) {
  const error = $("render-error");
  error.textContent = "";
  if (!state.scene) {
    error.textContent = "Pick or upload a scene first.";
    return;
  }
  if (!settings.validate()) return;
  button.disabled = true;
  try {
    const job = await submitJob({
      sceneId: state.scene.id,
      camera: shutter.apply(viewToCamera(viewer)),
      settings: reference ? { ...settings.settings(), ...REFERENCE_SETTINGS } : settings.settings(),
      outputs: settings.outputValues(),
      interactive: !reference && settings.interactive.checked,
      reference,
    });
    router.go(job.id);
  } catch (err) {
    error.textContent = `The job was refused: ${err.message}`;
  } finally {
    button.disabled = false;
  }
}

$("render-form").addEventListener("submit", (e) => {
  e.preventDefault();
  submitView(false, $("render-button"));
});
$("render-reference").addEventListener("click", () => submitView(true, $("render-reference")));

// --- jobs ---------------------------------------------------------------------

function stopFollowing() {
  follower.stop();
  tiles.close();
  overlay.setRunning([]);
}

function showJob(job) {
  state.job = job;
  jobPanel.show(job);
  const done = stateOf(job) === "DONE";
  layers.setJob(job, done);
  image.setJob(job, done);
  reference.setJob(job, done);
  debug.setJob(job);
  if (isFinal(job)) overlay.setRunning([]);
}

async function openJob(id) {
  stopFollowing();
  let job;
  try {
    job = await follower.open(id);
    if (!job) return; // another job was opened meanwhile
  } catch (e) {
    state.job = null;
    $("job-title").textContent = `Job ${id}`;
    $("job-error").hidden = false;
    $("job-error").textContent = e.message;
    return;
  }
  $("job-error").hidden = true;
  const { width, height } = job.request.settings;
  settings.show(job.request.settings, job.request.outputs, job.request.interactive);
  await selectScene(job.request.sceneId, job.request.camera);
  if (follower.jobId !== id) return;
  shutter.set(job.request.camera?.shutterClose ?? null);
  jobPanel.setTilesReceived(0);
  overlay.resize(width, height);
  debug.clear();
  showJob(job);
  state.running = new RunningTiles();
  tiles.open(job.id, width, height); // its records come to `follower`
  jobPanel.refreshHistory();
  user.refresh(); // one more queued
}

tiles.addEventListener("started", (e) => {
  state.running?.started(e.detail);
  overlay.setRunning(state.running?.running() ?? []);
});
tiles.addEventListener("tiles", (e) => {
  jobPanel.setTilesReceived(e.detail.received);
  state.running?.finish(e.detail.tiles);
  overlay.setRunning(state.running?.running() ?? []);
});
follower.addEventListener("job", (e) => showJob(e.detail));
follower.addEventListener("end", (e) => {
  overlay.setRunning([]);
  showJob(e.detail);
  jobPanel.refreshHistory();
  user.refresh(); // its files stored, one fewer queued
});
tiles.addEventListener("streamerror", (e) => {
  $("job-error").hidden = false;
  $("job-error").textContent = `Tile stream: ${e.detail}`;
});
jobPanel.addEventListener("open", (e) => router.go(e.detail));
jobPanel.addEventListener("cancelled", () => {
  jobPanel.refreshHistory();
  user.refresh();
});
jobPanel.addEventListener("deleted", (e) => {
  if (state.job?.id === e.detail) router.go(null); // the open job is gone
  jobPanel.refreshHistory();
  user.refresh();
});
layers.addEventListener("error", (e) => {
  $("job-error").hidden = false;
  $("job-error").textContent = e.detail;
});

router.addEventListener("route", (e) => {
  if (e.detail.jobId) openJob(e.detail.jobId);
  else stopFollowing();
});

// --- start ----------------------------------------------------------------------

async function start() {
  try {
    const h = await health();
    $("server-status").textContent = `${h.status} · ${h.workers} workers, ${h.threads} threads`
      + ` · data ${formatBytes(h.data_bytes ?? 0)}, ${formatBytes(h.free_bytes ?? 0)} free`;
    $("server-status").dataset.kind = h.status === "ok" ? "ok" : "error";
  } catch (e) {
    $("server-status").textContent = `server unreachable: ${e.message}`;
    $("server-status").dataset.kind = "error";
  }
  await user.refresh();
  scenes.sharedReadOnly = user.named;
  const list = await scenes.refresh();
  jobPanel.refreshHistory();
  if (router.jobId) {
    router.start();
  } else {
    const remembered = localStorage.getItem("rt.scene");
    const pick = list.find((s) => s.id === remembered) ?? list[0];
    if (pick) await selectScene(pick.id);
  }
}

// For the console and the browser tests: the live objects, read-only by convention.
window.rt = {
  viewer, settings, projection, shutter, user, scenes, jobPanel, tiles, follower, overlay, layers, debug, image, views, wipe, reference, router, state,
};
start();
