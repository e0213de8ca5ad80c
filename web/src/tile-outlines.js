// Outlines over the image: the tiles being rendered now and the pixel being
// debugged. Workers announce each tile they start (a TileRegion on the tile
// stream); a tile is outlined from then until its pixels arrive.

const keyOf = (t) => `${t.pass},${t.x},${t.y}`;

export class RunningTiles {
  constructor() {
    this.rects = new Map(); // "pass,x,y" -> the started tile
    this.finished = new Set(); // tiles whose pixels came before their announcement
  }

  started(tile) {
    if (!this.finished.has(keyOf(tile))) this.rects.set(keyOf(tile), tile);
  }

  finish(tiles) {
    for (const { region } of tiles) {
      this.rects.delete(keyOf(region));
      this.finished.add(keyOf(region));
    }
  }

  running() {
    return [...this.rects.values()];
  }
}

export class ImageOverlay {
  constructor(canvas) {
    this.canvas = canvas;
    this.ctx = canvas.getContext("2d", { willReadFrequently: true });
    this.running = [];
    this.pixel = null;
  }

  resize(width, height) {
    this.canvas.width = width;
    this.canvas.height = height;
    this.draw();
  }

  setRunning(rects) {
    this.running = rects;
    this.draw();
  }

  setPixel(pixel) {
    this.pixel = pixel;
    this.draw();
  }

  draw() {
    const { ctx, canvas } = this;
    ctx.clearRect(0, 0, canvas.width, canvas.height);
    const line = Math.max(1, Math.round(Math.max(canvas.width, canvas.height) / 400));
    ctx.lineWidth = line;
    ctx.setLineDash([4 * line, 3 * line]);
    ctx.strokeStyle = "#ffb020";
    for (const r of this.running) ctx.strokeRect(r.x + line / 2, r.y + line / 2, r.w - line, r.h - line);
    ctx.setLineDash([]);
    if (this.pixel) {
      const [x, y] = this.pixel;
      const arm = 6 * line;
      ctx.strokeStyle = "#000";
      ctx.lineWidth = line * 3;
      this._cross(x + 0.5, y + 0.5, arm);
      ctx.strokeStyle = "#35f0ff";
      ctx.lineWidth = line;
      this._cross(x + 0.5, y + 0.5, arm);
    }
  }

  _cross(x, y, arm) {
    const { ctx } = this;
    ctx.beginPath();
    ctx.moveTo(x - arm, y);
    ctx.lineTo(x - arm / 3, y);
    ctx.moveTo(x + arm / 3, y);
    ctx.lineTo(x + arm, y);
    ctx.moveTo(x, y - arm);
    ctx.lineTo(x, y - arm / 3);
    ctx.moveTo(x, y + arm / 3);
    ctx.lineTo(x, y + arm);
    ctx.stroke();
  }
}
