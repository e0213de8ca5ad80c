// The 3D view's projection switch (Perspective / Orthographic) and, for an
// orthographic view, its height in world units: what "Render this view" sends
// as rt.Camera.projection and ortho_height. A scene camera that is
// orthographic sets both when chosen; dollying changes the height.
const format = (v) => String(Number(v.toPrecision(6)));

export class ProjectionControl extends EventTarget {
  constructor(root, viewer) {
    super();
    this.viewer = viewer;
    this.select = root.getElementById("view-projection");
    this.heightField = root.getElementById("ortho-height-field");
    this.height = root.getElementById("view-ortho-height");
    // The settings panel's field of view, of no use to an orthographic view (the perspective one keeps it).
    this.fovField = root.getElementById("camera-fov_y")?.closest(".field") ?? null;
    this.select.addEventListener("change", () => {
      viewer.setProjection(this.select.value === "orthographic");
      this.dispatchEvent(new Event("change"));
    });
    this.height.addEventListener("input", () => {
      const value = Number(this.height.value);
      if (!(value > 0) || !Number.isFinite(value)) {
        this.height.setCustomValidity("The height must be a positive number of world units.");
        return;
      }
      this.height.setCustomValidity("");
      viewer.setProjection(true, value);
      this.dispatchEvent(new Event("change"));
    });
    viewer.addEventListener("camerachange", () => this.show());
    this.show();
  }

  /** Shows the view's projection and height. */
  show() {
    const ortho = this.viewer.orthographic;
    this.select.value = ortho ? "orthographic" : "perspective";
    this.heightField.hidden = !ortho;
    if (this.fovField) this.fovField.hidden = ortho;
    if (ortho && document.activeElement !== this.height) this.height.value = format(this.viewer.viewHeight);
  }
}
