// The float channels of an OpenEXR file as rtcore writes it (scanlines, ZIP
// blocks of 16 lines, FLOAT channels), for tests that hold the viewer's
// numbers against the file itself: the same decoding as
// tests/renderer/test_cli.py's read_exr_colour, independent of the viewer's.
import { inflateSync } from "node:zlib";

/** {width, height, channels: {name: Float32Array (row-major)}} */
export function readExr(bytes) {
  const data = Buffer.from(bytes);
  if (data.readUInt32LE(0) !== 20000630) throw new Error("not an OpenEXR file");
  const header = {};
  let at = 8;
  while (data[at] !== 0) {
    const nameEnd = data.indexOf(0, at);
    const typeEnd = data.indexOf(0, nameEnd + 1);
    const size = data.readInt32LE(typeEnd + 1);
    header[data.toString("latin1", at, nameEnd)] = data.subarray(typeEnd + 5, typeEnd + 5 + size);
    at = typeEnd + 5 + size;
  }
  if (header.compression[0] !== 3) throw new Error(`compression ${header.compression[0]}, not ZIP`);
  const names = [];
  for (let i = 0; header.channels[i] !== 0;) {
    const end = header.channels.indexOf(0, i);
    names.push(header.channels.toString("latin1", i, end));
    if (header.channels.readInt32LE(end + 1) !== 2) throw new Error("a channel that is not FLOAT");
    i = end + 1 + 16;
  }
  const window = header.dataWindow;
  const [x0, y0, x1, y1] = [0, 4, 8, 12].map((o) => window.readInt32LE(o));
  const width = x1 - x0 + 1;
  const height = y1 - y0 + 1;
  const channels = Object.fromEntries(names.map((n) => [n, new Float32Array(width * height)]));
  const blocks = Math.ceil(height / 16);
  for (let b = 0; b < blocks; ++b) {
    const offset = Number(data.readBigUInt64LE(at + 1 + 8 * b));
    const y = data.readInt32LE(offset) - y0;
    const size = data.readInt32LE(offset + 4);
    const packed = inflateSync(data.subarray(offset + 8, offset + 8 + size));
    // OpenEXR's byte predictor, then its split of even and odd bytes.
    const split = Buffer.alloc(packed.length);
    let previous = 0;
    for (let i = 0; i < packed.length; ++i) previous = split[i] = (i ? previous + packed[i] - 128 : packed[i]) & 255;
    const raw = Buffer.alloc(split.length);
    const half = (split.length + 1) >> 1;
    for (let i = 0; i < split.length; ++i) raw[i] = i % 2 ? split[half + (i >> 1)] : split[i >> 1];
    const rows = Math.min(16, height - y);
    for (let r = 0; r < rows; ++r) {
      names.forEach((name, c) => {
        for (let x = 0; x < width; ++x) {
          channels[name][(y + r) * width + x] = raw.readFloatLE(4 * ((r * names.length + c) * width + x));
        }
      });
    }
  }
  return { width, height, channels };
}
