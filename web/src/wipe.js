// The render laid over the 3D view at the job's camera, with a handle
// between them: the 3D view left of it, the render right. Drag the handle,
// or move it with the arrow keys. The image keeps to the 3D canvas's own
// rectangle, which has the job's aspect, so the two line up pixel for pixel.

export class Wipe {
  constructor(view, frame, handle) {
    this.view = view;
    this.frame = frame; // the 3D view's canvas
    this.handle = handle;
    this.fraction = 0.5;
    this.on = false;
    new ResizeObserver(() => this.on && this._place()).observe(frame);
    handle.addEventListener("pointerdown", (e) => {
      handle.setPointerCapture(e.pointerId);
      this._dragging = true;
    });
    handle.addEventListener("pointermove", (e) => {
      if (!this._dragging) return;
      const rect = frame.getBoundingClientRect();
      this.set((e.clientX - rect.left) / rect.width);
    });
    handle.addEventListener("pointerup", () => { this._dragging = false; });
    handle.addEventListener("keydown", (e) => {
      const step = { ArrowLeft: -0.02, ArrowRight: 0.02, Home: -1, End: 1 }[e.key];
      if (step === undefined) return;
      e.preventDefault();
      this.set(this.fraction + step);
    });
  }

  enable(on) {
    this.on = on;
    this.handle.hidden = !on;
    if (on) this._place();
    else this.view.setWipe(null, null);
  }

  /** The handle at `fraction` of the 3D view's width from its left. */
  set(fraction) {
    this.fraction = Math.min(1, Math.max(0, fraction));
    this._place();
  }

  _place() {
    const stage = this.view.canvas.getBoundingClientRect();
    const rect = this.frame.getBoundingClientRect();
    const x = rect.left - stage.left + this.fraction * rect.width;
    this.handle.style.left = `${x}px`;
    this.handle.setAttribute("aria-valuenow", String(Math.round(this.fraction * 100)));
    this.view.setWipe(this.frame, x);
  }
}
