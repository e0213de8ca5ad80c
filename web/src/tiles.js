// A job's image as its tiles stream in: the WebSocket's rt.TileStreamMessage
// frames are decoded with the generated code, queued, and painted once per
// animation frame. Preview tiles (scale > 1) cover each sample's whole block;
// full-resolution tiles are put as they are, so the finished canvas holds
// exactly the bytes of image.png. The job's records on the stream (`job` as it
// changes, `end` at its end) are handed on as events, for JobFollower.
import { tileStreamUrl } from "./api.js";
import { parseBinary } from "./proto.js";

export class TileView extends EventTarget {
  constructor(canvas) {
    super();
    this.canvas = canvas;
    // A CPU-backed canvas: putImageData lands exactly, and reading it back (tests, the
    // debugger) never waits for a GPU copy.
    this.ctx = canvas.getContext("2d", { willReadFrequently: true });
    this.scratch = document.createElement("canvas");
    this.queue = [];
    this.socket = null;
    this.jobId = null;
    this.received = 0;
    this._frame = null;
  }

  /** Clears the canvas to a w x h image and follows the job's tile stream. */
  open(jobId, width, height) {
    this.close();
    this.jobId = jobId;
    this.received = 0;
    this.canvas.width = width;
    this.canvas.height = height;
    this.ctx.fillStyle = "#000";
    this.ctx.fillRect(0, 0, width, height);
    const socket = new WebSocket(tileStreamUrl(jobId));
    socket.binaryType = "arraybuffer";
    socket.addEventListener("message", (e) => this._message(socket, e.data));
    socket.addEventListener("close", (e) => {
      if (this.socket !== socket) return;
      this.socket = null;
      if (!this._ended) {
        const reason = e.reason || (e.code === 1000 ? "the server closed the tile stream" : `connection lost (code ${e.code})`);
        this.dispatchEvent(new CustomEvent("streamerror", { detail: reason }));
      }
    });
    this._ended = false;
    this.socket = socket;
  }

  close() {
    if (this.socket) {
      const socket = this.socket;
      this.socket = null;
      socket.close();
    }
    this.queue.length = 0;
    if (this._frame !== null) cancelAnimationFrame(this._frame);
    this._frame = null;
  }

  _message(socket, data) {
    if (this.socket !== socket) return;
    let message;
    try {
      message = parseBinary("TileStreamMessage", data);
    } catch (e) {
      this.dispatchEvent(new CustomEvent("streamerror", { detail: `a tile frame could not be read: ${e.message}` }));
      return;
    }
    if (message.message.case === "tile") {
      this.queue.push(message.message.value);
      if (this._frame === null) this._frame = requestAnimationFrame(() => this._paint());
    } else if (message.message.case === "started") {
      this.dispatchEvent(new CustomEvent("started", { detail: message.message.value }));
    } else if (message.message.case === "job") {
      this.dispatchEvent(new CustomEvent("job", { detail: message.message.value }));
    } else if (message.message.case === "end") {
      this._ended = true;
      this._paint();
      this.dispatchEvent(new CustomEvent("end", { detail: message.message.value }));
    }
  }

  _paint() {
    this._frame = null;
    const tiles = this.queue.splice(0);
    for (const tile of tiles) this._draw(tile);
    this.received += tiles.length;
    if (tiles.length) this.dispatchEvent(new CustomEvent("tiles", { detail: { tiles, received: this.received } }));
  }

  _draw(tile) {
    const { x, y, w, h } = tile.region;
    const scale = Math.max(tile.scale, 1);
    const sw = Math.ceil(w / scale);
    const sh = Math.ceil(h / scale);
    if (tile.pixels.length !== sw * sh * 4) {
      this.dispatchEvent(new CustomEvent("streamerror", {
        detail: `tile at (${x}, ${y}) has ${tile.pixels.length} bytes, expected ${sw * sh * 4}`,
      }));
      return;
    }
    const image = new ImageData(new Uint8ClampedArray(tile.pixels), sw, sh);
    if (scale === 1) {
      this.ctx.putImageData(image, x, y);
      return;
    }
    this.scratch.width = sw;
    this.scratch.height = sh;
    this.scratch.getContext("2d").putImageData(image, 0, 0);
    const ctx = this.ctx;
    ctx.save();
    ctx.beginPath();
    ctx.rect(x, y, w, h);
    ctx.clip();
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(this.scratch, 0, 0, sw, sh, x, y, sw * scale, sh * scale);
    ctx.restore();
  }

  /** Image pixel under a pointer event, or null outside the image. */
  pixelAt(event) {
    const rect = this.canvas.getBoundingClientRect();
    const x = Math.floor(((event.clientX - rect.left) / rect.width) * this.canvas.width);
    const y = Math.floor(((event.clientY - rect.top) / rect.height) * this.canvas.height);
    if (x < 0 || y < 0 || x >= this.canvas.width || y >= this.canvas.height) return null;
    return [x, y];
  }
}
