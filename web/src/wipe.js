// The render laid over the 3D view at the job's camera, with a handle
// between them: the 3D view left of it, the render right. The image keeps to
// the 3D canvas's own rectangle, which has the job's aspect, so the two line
// up pixel for pixel.
import { DragHandle } from "./drag-handle.js";

export class Wipe {
  constructor(view, frame, handle) {
    this.view = view;
    this.frame = frame; // the 3D view's canvas
    this.on = false;
    this.line = new DragHandle(handle, () => frame.getBoundingClientRect(), (x) => {
      if (this.on) view.setWipe(frame, x);
    });
    new ResizeObserver(() => this.on && this.line.place()).observe(frame);
  }

  get fraction() {
    return this.line.fraction;
  }

  enable(on) {
    this.on = on;
    this.line.show(on);
    if (!on) this.view.setWipe(null, null);
  }
}
