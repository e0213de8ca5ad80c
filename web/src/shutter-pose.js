// Camera motion for motion blur (rt.Camera.shutter_close): the view a job is
// rendered from is where the camera is when the shutter opens; "Mark" keeps the
// view of that moment as where it is when the shutter closes, so a user orbits
// to the end pose, marks it, orbits back to the start and renders.
import { create, schema } from "./proto.js";

const round = (v) => Math.fround(v);
const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
const format = (v) => (v < 0.001 ? v.toExponential(1) : v.toPrecision(3));

export class ShutterPose {
  constructor(doc, viewer) {
    this.viewer = viewer;
    this.markButton = doc.getElementById("shutter-mark");
    this.clearButton = doc.getElementById("shutter-clear");
    this.status = doc.getElementById("shutter-status");
    this.pose = null; // rt.CameraPose, or null for a still camera
    this.markButton.addEventListener("click", () => this.mark());
    this.clearButton.addEventListener("click", () => this.set(null));
    // Once an orbit ends, not on every frame of it: rewriting the text re-lays
    // out the panel, which a software-rendered page pays for in frame rate.
    viewer.addEventListener("orbitend", () => this._describe());
    this._describe();
  }

  /** The 3D view's pose, from now on where the camera is when the shutter closes. */
  mark() {
    const { camera, controls } = this.viewer;
    this.set(create(schema("CameraPose"), {
      position: camera.position.toArray().map(round),
      target: controls.target.toArray().map(round),
      up: camera.up.toArray().map(round),
    }));
  }

  /** `camera` (an rt.Camera of the view) with the marked pose, if any. */
  apply(camera) {
    if (this.pose) camera.shutterClose = this.pose;
    return camera;
  }

  /** Shows a job's or a scene camera's shutter-close pose (null: still). */
  set(pose) {
    this.pose = pose && pose.position?.length === 3 ? pose : null;
    this._describe();
  }

  _describe() {
    this.clearButton.hidden = !this.pose;
    if (!this.pose) {
      this.status.textContent = "Still: the camera does not move while the shutter is open.";
      return;
    }
    const { camera, controls } = this.viewer;
    const moved = distance(camera.position.toArray(), this.pose.position);
    const turned = distance(controls.target.toArray(), this.pose.target);
    this.status.textContent = `While the shutter is open the camera moves ${format(moved)} and its target `
      + `${format(turned)} from this view to the marked one (motion blur in the settings).`;
  }
}
