// A vertical line the user drags (or moves with the arrow keys, Home and
// End) across a rectangle: the split of a wipe. It keeps a fraction of the
// rectangle's width, places itself there within its positioned parent, and
// reports the line's x in CSS pixels from the parent's left.

export class DragHandle {
  /** `bounds()`: the rectangle (a DOMRect) it moves across; `onMove(x)`: where the line now is. */
  constructor(handle, bounds, onMove) {
    this.handle = handle;
    this.bounds = bounds;
    this.onMove = onMove;
    this.fraction = 0.5;
    handle.addEventListener("pointerdown", (e) => {
      e.stopPropagation();
      handle.setPointerCapture(e.pointerId);
      this._dragging = true;
    });
    handle.addEventListener("pointermove", (e) => {
      if (!this._dragging) return;
      const rect = this.bounds();
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

  show(on) {
    this.handle.hidden = !on;
    if (on) this.place();
  }

  set(fraction) {
    this.fraction = Math.min(1, Math.max(0, fraction));
    this.place();
  }

  /** Puts the line back at its fraction (the rectangle moved or changed size). */
  place() {
    const parent = this.handle.offsetParent?.getBoundingClientRect() ?? { left: 0 };
    const rect = this.bounds();
    const x = rect.left - parent.left + this.fraction * rect.width;
    this.handle.style.left = `${x}px`;
    this.handle.setAttribute("aria-valuenow", String(Math.round(this.fraction * 100)));
    this.onMove(x);
  }
}
