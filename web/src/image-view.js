// The render filling the main area, as an HDR viewer shows it: zoom with the
// wheel around the cursor (to 64x, sharp texels past 1:1), pan by dragging,
// fit and 1:1, a rectangle dragged with Shift for statistics, a click to pick
// a pixel. It draws whatever canvas it is given (the streaming tiles, or the
// linear layers through the display controls) and knows nothing of either.
//
// Events: "hover" (detail: [x, y] or null), "pick" ([x, y]), "select"
// ({x0, y0, x1, y1}, pixel edges, or null when cleared), "zoom" (the scale).

const MAX_SCALE = 64;
const CLICK_SLOP = 3; // CSS pixels a press may move and still be a click

export class ImageView extends EventTarget {
  constructor(canvas) {
    super();
    this.canvas = canvas;
    this.ctx = canvas.getContext("2d");
    this.source = null;
    this.width = 0;
    this.height = 0;
    this.scale = 1;
    this.offset = [0, 0]; // CSS pixels from the canvas's corner to the image's
    this.fitted = true; // refit when the canvas or the image changes size
    this.selection = null;
    this.marker = null;
    this.frame = null; // an element the image is laid over exactly (the wipe's 3D view), or null
    this.wipe = null; // CSS pixels from the left where the image starts showing, or null: all of it
    this.second = null; // drawn over the image right of `split` CSS pixels (A | B), or null
    this.split = 0;
    this._frame = null;
    this._drag = null;
    new ResizeObserver(() => this._resize()).observe(canvas);
    this._wirePointer();
    this._wireKeys();
  }

  /** Draws `source` (a canvas or image of width x height); a new size refits. */
  setSource(source, width, height) {
    const resized = width !== this.width || height !== this.height;
    this.source = source;
    this.width = width;
    this.height = height;
    if (resized) {
      this.selection = null;
      this.fitted = true;
    }
    if (this.fitted) this.fit();
    else this.invalidate();
  }

  /** Redraws at the next frame (the source changed). */
  invalidate() {
    if (this._frame === null) this._frame = requestAnimationFrame(() => this._draw());
  }

  get _cssSize() {
    return [this.canvas.clientWidth, this.canvas.clientHeight];
  }

  fit() {
    const [w, h] = this._cssSize;
    this.fitted = true;
    if (!this.width || !w || !h) return this.invalidate();
    if (this.frame) {
      // Over the frame's own pixels: the 3D view at the job's camera has the image's aspect.
      const mine = this.canvas.getBoundingClientRect();
      const theirs = this.frame.getBoundingClientRect();
      this.scale = theirs.width / this.width;
      this.offset = [theirs.left - mine.left, theirs.top - mine.top];
      return this._zoomed();
    }
    this.scale = Math.min(w / this.width, h / this.height);
    this.offset = [(w - this.width * this.scale) / 2, (h - this.height * this.scale) / 2];
    this._zoomed();
  }

  /** One image pixel to one CSS pixel, centred. */
  actualSize() {
    const [w, h] = this._cssSize;
    this.fitted = false;
    this.scale = 1;
    this.offset = [Math.round((w - this.width) / 2), Math.round((h - this.height) / 2)];
    this._zoomed();
  }

  /** Zooms by `factor` keeping the image point under (cx, cy) (CSS pixels in the canvas) in place. */
  zoomAt(factor, cx, cy) {
    const [w, h] = this._cssSize;
    if (!this.width || !w || !h) return;
    const least = Math.min(1, w / this.width, h / this.height) / 8;
    const scale = Math.min(MAX_SCALE, Math.max(least, this.scale * factor));
    const ix = (cx - this.offset[0]) / this.scale;
    const iy = (cy - this.offset[1]) / this.scale;
    this.scale = scale;
    this.offset = [cx - ix * scale, cy - iy * scale];
    this.fitted = false;
    this._zoomed();
  }

  /** The image pixel under a pointer event, or null off the image. */
  pixelAt(event) {
    const rect = this.canvas.getBoundingClientRect();
    const x = Math.floor((event.clientX - rect.left - this.offset[0]) / this.scale);
    const y = Math.floor((event.clientY - rect.top - this.offset[1]) / this.scale);
    return x >= 0 && y >= 0 && x < this.width && y < this.height ? [x, y] : null;
  }

  /**
   * Lays the image exactly over `element` (null: back to zoom and pan), and
   * shows it only right of `wipe` CSS pixels from the canvas's left (null: all).
   */
  setWipe(element, wipe) {
    this.frame = element;
    this.wipe = element ? wipe : null;
    this.fit();
  }

  /** Shows `source` (the same size as the image) instead of it right of `split` CSS pixels; null: none. */
  setSecond(source, split) {
    this.second = source;
    this.split = split;
    this.invalidate();
  }

  /** Marks a pixel (the one the debugger traced), or nothing. */
  setMarker(pixel) {
    this.marker = pixel;
    this.invalidate();
  }

  clearSelection() {
    this.selection = null;
    this.invalidate();
    this.dispatchEvent(new CustomEvent("select", { detail: null }));
  }

  _zoomed() {
    this.invalidate();
    this.dispatchEvent(new CustomEvent("zoom", { detail: this.scale }));
  }

  _resize() {
    const dpr = window.devicePixelRatio || 1;
    const [w, h] = this._cssSize;
    this.canvas.width = Math.max(1, Math.round(w * dpr));
    this.canvas.height = Math.max(1, Math.round(h * dpr));
    if (this.fitted) this.fit();
    else this.invalidate();
  }

  _draw() {
    this._frame = null;
    const ctx = this.ctx;
    const dpr = this.canvas.width / Math.max(1, this.canvas.clientWidth);
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.clearRect(0, 0, this.canvas.width, this.canvas.height);
    if (!this.source || !this.width) return;
    // Past 1:1 each texel is a sharp square, as tev shows them.
    ctx.imageSmoothingEnabled = this.scale < 1;
    this._drawImage(this.source, this.wipe ?? -Infinity, dpr);
    if (this.second) this._drawImage(this.second, this.split, dpr);
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.lineWidth = 1;
    if (this.selection) {
      const { x0, y0, x1, y1 } = this.selection;
      const [sx, sy] = this._toScreen(Math.min(x0, x1), Math.min(y0, y1));
      const [ex, ey] = this._toScreen(Math.max(x0, x1), Math.max(y0, y1));
      ctx.setLineDash([4, 3]);
      ctx.strokeStyle = "#fff";
      ctx.strokeRect(sx + 0.5, sy + 0.5, ex - sx, ey - sy);
      ctx.setLineDash([]);
    }
    if (this.marker) {
      const [sx, sy] = this._toScreen(this.marker[0], this.marker[1]);
      const size = Math.max(this.scale, 6);
      ctx.strokeStyle = "#ffd54a";
      ctx.strokeRect(sx + this.scale / 2 - size / 2 - 1, sy + this.scale / 2 - size / 2 - 1, size + 2, size + 2);
    }
  }

  /** Draws `image` where the image lies, only right of `left` CSS pixels. */
  _drawImage(image, left, dpr) {
    const ctx = this.ctx;
    ctx.save();
    if (left > -Infinity) {
      ctx.setTransform(1, 0, 0, 1, 0, 0);
      ctx.beginPath();
      ctx.rect(dpr * left, 0, this.canvas.width, this.canvas.height);
      ctx.clip();
    }
    ctx.setTransform(dpr * this.scale, 0, 0, dpr * this.scale, dpr * this.offset[0], dpr * this.offset[1]);
    ctx.drawImage(image, 0, 0, this.width, this.height);
    ctx.restore();
  }

  _toScreen(x, y) {
    return [this.offset[0] + x * this.scale, this.offset[1] + y * this.scale];
  }

  /** Image coordinates (unclamped, fractional) of a pointer event. */
  _imagePoint(event) {
    const rect = this.canvas.getBoundingClientRect();
    return [(event.clientX - rect.left - this.offset[0]) / this.scale,
      (event.clientY - rect.top - this.offset[1]) / this.scale];
  }

  _wirePointer() {
    const canvas = this.canvas;
    canvas.addEventListener("wheel", (e) => {
      e.preventDefault();
      const rect = canvas.getBoundingClientRect();
      // Lines and pages as pixels (about 40 a line), so a mouse notch zooms by about 1.2x.
      const pixels = e.deltaY * (e.deltaMode === 1 ? 40 : e.deltaMode === 2 ? 800 : 1);
      this.zoomAt(Math.exp(-pixels * 0.0045), e.clientX - rect.left, e.clientY - rect.top);
    }, { passive: false });
    canvas.addEventListener("pointerdown", (e) => {
      if (e.button !== 0) return;
      canvas.setPointerCapture(e.pointerId);
      this._drag = { x: e.clientX, y: e.clientY, offset: [...this.offset], moved: false,
        select: e.shiftKey, start: this._imagePoint(e) };
    });
    canvas.addEventListener("pointermove", (e) => {
      this.dispatchEvent(new CustomEvent("hover", { detail: this.pixelAt(e) }));
      const drag = this._drag;
      if (!drag) return;
      const dx = e.clientX - drag.x;
      const dy = e.clientY - drag.y;
      drag.moved = drag.moved || Math.hypot(dx, dy) > CLICK_SLOP;
      if (!drag.moved) return;
      if (drag.select) {
        this.selection = this._pixelRect(drag.start, this._imagePoint(e));
      } else {
        this.offset = [drag.offset[0] + dx, drag.offset[1] + dy];
        this.fitted = false;
      }
      this.invalidate();
    });
    canvas.addEventListener("pointerleave", () => this.dispatchEvent(new CustomEvent("hover", { detail: null })));
    canvas.addEventListener("pointerup", (e) => {
      const drag = this._drag;
      this._drag = null;
      if (!drag) return;
      if (!drag.moved) {
        const pixel = this.pixelAt(e);
        if (pixel) this.dispatchEvent(new CustomEvent("pick", { detail: pixel }));
      } else if (drag.select && this.selection) {
        this.dispatchEvent(new CustomEvent("select", { detail: this.selection }));
      }
    });
  }

  /** The whole pixels two image points span, clipped to the image. */
  _pixelRect([ax, ay], [bx, by]) {
    const clamp = (v, hi) => Math.min(Math.max(v, 0), hi);
    return {
      x0: clamp(Math.floor(Math.min(ax, bx)), this.width), y0: clamp(Math.floor(Math.min(ay, by)), this.height),
      x1: clamp(Math.ceil(Math.max(ax, bx)), this.width), y1: clamp(Math.ceil(Math.max(ay, by)), this.height),
    };
  }

  _wireKeys() {
    this.canvas.addEventListener("keydown", (e) => {
      const [w, h] = this._cssSize;
      const keys = {
        f: () => this.fit(), 1: () => this.actualSize(), "+": () => this.zoomAt(2, w / 2, h / 2),
        "=": () => this.zoomAt(2, w / 2, h / 2), "-": () => this.zoomAt(0.5, w / 2, h / 2),
        Escape: () => this.clearSelection(),
      };
      if (keys[e.key] && !e.ctrlKey && !e.metaKey) {
        e.preventDefault();
        keys[e.key]();
      }
    });
  }
}
