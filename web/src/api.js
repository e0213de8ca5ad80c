// The job service's REST API. Answers are parsed into the generated messages;
// a refused request throws an ApiError carrying the server's own words.
// A server started with RT_API_TOKEN answers 401 until the viewer sends the
// token: the user is asked for it once, and it is kept in this browser.
import { parseBinary, parseJson, toJsonBody } from "./proto.js";

const TOKEN_KEY = "rt-api-token";
let token = localStorage.getItem(TOKEN_KEY) ?? "";

const authHeaders = () => (token ? { Authorization: `Bearer ${token}` } : {});

/** `path` with the token as a query parameter, for what cannot send headers (links, images, WebSockets). */
function withToken(path) {
  return token ? `${path}${path.includes("?") ? "&" : "?"}token=${encodeURIComponent(token)}` : path;
}

/** Asks the user for the server's token after a 401; true when one was given. */
function askForToken(message) {
  const given = window.prompt(`${message}\nEnter this server's API token:`, "");
  if (!given) return false;
  token = given.trim();
  localStorage.setItem(TOKEN_KEY, token);
  return true;
}

/** Whether this browser holds a token for the server. */
export const hasToken = () => Boolean(token);

/** Forgets the token (signing out): the next refused request asks for one again. */
export function forgetToken() {
  token = "";
  localStorage.removeItem(TOKEN_KEY);
}

export class ApiError extends Error {
  constructor(message, status) {
    super(message);
    this.status = status;
  }
}

function problem(status, body, fallback) {
  let detail = fallback;
  try {
    const parsed = typeof body === "string" ? JSON.parse(body) : body;
    if (parsed && typeof parsed.detail === "string") detail = parsed.detail;
  } catch {
    // not JSON: a proxy's or the network's answer
  }
  return new ApiError(detail, status);
}

async function request(method, path, body, retried = false) {
  let response;
  try {
    response = await fetch(path, {
      method,
      headers: { ...authHeaders(), ...(body === undefined ? {} : { "Content-Type": "application/json" }) },
      body: body === undefined ? undefined : JSON.stringify(body),
    });
  } catch (e) {
    throw new ApiError(`cannot reach the server (${e.message})`, 0);
  }
  if (response.status === 401 && !retried) {
    const refused = problem(401, await response.text(), "this server needs an API token");
    if (askForToken(refused.message)) return request(method, path, body, true);
    throw refused;
  }
  if (!response.ok) {
    throw problem(response.status, await response.text(), `${method} ${path}: HTTP ${response.status}`);
  }
  return response.status === 204 ? null : response.json();
}

/** GET of a binary answer (serialized proto) as bytes; refusals as request() throws them. */
async function requestBytes(path, retried = false) {
  let response;
  try {
    response = await fetch(path, { headers: authHeaders() });
  } catch (e) {
    throw new ApiError(`cannot reach the server (${e.message})`, 0);
  }
  if (response.status === 401 && !retried) {
    const refused = problem(401, await response.text(), "this server needs an API token");
    if (askForToken(refused.message)) return requestBytes(path, true);
    throw refused;
  }
  if (!response.ok) throw problem(response.status, await response.text(), `GET ${path}: HTTP ${response.status}`);
  return new Uint8Array(await response.arrayBuffer());
}

export async function listScenes() {
  return parseJson("SceneList", await request("GET", "/api/scenes")).scenes;
}

export async function getScene(id) {
  return parseJson("SceneInfo", await request("GET", `/api/scenes/${encodeURIComponent(id)}`));
}

export function deleteScene(id) {
  return request("DELETE", `/api/scenes/${encodeURIComponent(id)}`);
}

export const modelUrl = (sceneId) => withToken(`/api/scenes/${encodeURIComponent(sceneId)}/model.glb`);

/**
 * Uploads a scene file; onProgress(fraction) follows the bytes sent. Resolves
 * to the rt.SceneInfo; rejects with ApiError naming why the server refused it.
 */
export function uploadScene(file, onProgress = () => {}) {
  return new Promise((resolve, reject) => {
    const xhr = new XMLHttpRequest();
    xhr.open("POST", "/api/scenes");
    for (const [name, value] of Object.entries(authHeaders())) xhr.setRequestHeader(name, value);
    xhr.responseType = "text";
    xhr.upload.addEventListener("progress", (e) => {
      if (e.lengthComputable) onProgress(e.loaded / e.total);
    });
    xhr.addEventListener("load", () => {
      if (xhr.status >= 200 && xhr.status < 300) {
        try {
          resolve(parseJson("SceneInfo", JSON.parse(xhr.responseText)));
        } catch (e) {
          reject(new ApiError(`the server's answer could not be read: ${e.message}`, xhr.status));
        }
      } else {
        reject(problem(xhr.status, xhr.responseText, `upload refused (HTTP ${xhr.status})`));
      }
    });
    xhr.addEventListener("error", () => reject(new ApiError("the upload failed: cannot reach the server", 0)));
    xhr.addEventListener("abort", () => reject(new ApiError("the upload was cancelled", 0)));
    const form = new FormData();
    form.append("file", file, file.name);
    xhr.send(form);
  });
}

export async function submitJob(init) {
  return parseJson("Job", await request("POST", "/api/jobs", toJsonBody("JobRequest", init)));
}

export async function listJobs(offset = 0, limit = 20) {
  return parseJson("JobList", await request("GET", `/api/jobs?offset=${offset}&limit=${limit}`));
}

export async function getJob(id) {
  return parseJson("Job", await request("GET", `/api/jobs/${encodeURIComponent(id)}`));
}

/** DELETE: a queued or running job is cancelled (its record answered); one that has ended goes (null). */
export async function deleteJob(id) {
  const answer = await request("DELETE", `/api/jobs/${encodeURIComponent(id)}`);
  return answer === null ? null : parseJson("Job", answer);
}

/** Pins a job (kept whatever the retention policy says) or unpins it; answers its record. */
export async function pinJob(id, pinned) {
  return parseJson("Job", await request(pinned ? "PUT" : "DELETE", `/api/jobs/${encodeURIComponent(id)}/pin`));
}

/** Address of a finished job's image: "image" or an auxiliary output's name, .png or .exr. */
export const jobImageUrl = (jobId, name = "image", ext = "png") =>
  withToken(`/api/jobs/${encodeURIComponent(jobId)}/${name}.${ext}`);

/**
 * A done job's linear layer ("color" or an auxiliary output's name) as
 * {name, width, height, channels: [EXR channel names], values: Float32Array},
 * the pixels row by row from the top, channels interleaved.
 */
export async function jobLayer(jobId, name) {
  return decodeLayer(name, await requestBytes(`/api/jobs/${encodeURIComponent(jobId)}/layers/${name}`));
}

function decodeLayer(name, bytes) {
  const layer = parseBinary("Layer", bytes);
  const [height, width, count = 1] = layer.shape;
  if (layer.dtype !== "<f4" || layer.data.byteLength !== width * height * count * 4 || layer.channels.length !== count) {
    throw new ApiError(`layer ${name}: ${layer.shape.join("x")} ${layer.dtype} does not match its ${layer.data.byteLength} bytes`, 0);
  }
  // A copy: the bytes may sit at an offset a Float32Array cannot view. Little-endian, as every browser's CPU.
  const values = new Float32Array(layer.data.slice().buffer);
  return { name, width, height, channels: layer.channels, values };
}

/** Job `jobId`'s image measured against `referenceId`'s: rt.ImageComparison, over `rect` ({x, y, w, h}) or all. */
export async function compareJobs(jobId, referenceId, rect = null, referenceLayer = "color") {
  const region = rect ? { x: rect.x, y: rect.y, w: rect.w, h: rect.h } : {};
  return parseJson("ImageComparison", await request("GET", comparePath(jobId, referenceId, "", referenceLayer, region)));
}

/** The HDR-FLIP map of a job against a reference ("noisy": its image before denoising), as jobLayer answers a layer. */
export async function flipMap(jobId, referenceId, referenceLayer = "color") {
  return decodeLayer("flip", await requestBytes(comparePath(jobId, referenceId, "/flip", referenceLayer)));
}

/** /api/jobs/{job}/compare/{reference}{suffix}, with the reference's layer when not its colour. */
function comparePath(jobId, referenceId, suffix, referenceLayer, params = {}) {
  const query = new URLSearchParams(params);
  if (referenceLayer !== "color") query.set("reference_layer", referenceLayer);
  return `/api/jobs/${encodeURIComponent(jobId)}/compare/${encodeURIComponent(referenceId)}${suffix}`
    + (query.size ? `?${query}` : "");
}

/** Marks a done job as its view's reference; answers the scene's rt.SceneInfo. */
export async function markReference(sceneId, jobId) {
  const path = `/api/scenes/${encodeURIComponent(sceneId)}/references/${encodeURIComponent(jobId)}`;
  return parseJson("SceneInfo", await request("PUT", path));
}

/** The job's view's done jobs against its reference (rt.AccuracyPlot; no referenceId: the view has none). */
export async function jobAccuracy(jobId) {
  return parseJson("AccuracyPlot", await request("GET", `/api/jobs/${encodeURIComponent(jobId)}/accuracy`));
}

/** The colour ramp of the BVH cost heat map, low to high, as the server draws it. */
export const heatRampUrl = () => withToken("/api/jobs/legends/bvh_cost.png");

export function tileStreamUrl(jobId) {
  const scheme = location.protocol === "https:" ? "wss:" : "ws:";
  return `${scheme}//${location.host}${withToken(`/api/jobs/${encodeURIComponent(jobId)}/tiles`)}`;
}

export async function debugRay(sceneId, camera, settings, pixel) {
  const body = toJsonBody("DebugRayRequest", { camera, settings, pixel });
  return parseJson("DebugPath", await request("POST", `/api/scenes/${encodeURIComponent(sceneId)}/debug-ray`, body));
}

/** The boxes of one BVH level (level < 0: the leaves) of a tree: "top", "world" or an instance number. */
export async function bvhBoxes(sceneId, level, tree = "top") {
  const query = `${level < 0 ? "leaves=1" : `level=${level}`}&tree=${encodeURIComponent(tree)}`;
  return parseJson("BvhBoxes", await request("GET", `/api/scenes/${encodeURIComponent(sceneId)}/bvh?${query}`));
}

/** Who the token belongs to, and their use against the quotas (rt.UserInfo). */
export async function me() {
  return parseJson("UserInfo", await request("GET", "/api/me"));
}

export async function health() {
  return request("GET", "/api/health");
}
