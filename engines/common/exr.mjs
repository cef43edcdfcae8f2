// A single-channel f32 OpenEXR writer: uncompressed scanlines, row 0 at the top (INCREASING_Y).
// Hand-written because no maintained npm package writes EXR; an uncompressed file needs only
// the header attributes below, an offset table and one block per row (OpenEXR's file layout).

const FLOAT = 2; // OpenEXR pixel type
const NO_COMPRESSION = 0;
const INCREASING_Y = 0;

function attribute(name, type, value) {
  const head = Buffer.from(`${name}\0${type}\0`, 'latin1');
  const size = Buffer.alloc(4);
  size.writeInt32LE(value.length);
  return Buffer.concat([head, size, value]);
}

function int32s(...values) {
  const b = Buffer.alloc(4 * values.length);
  values.forEach((v, i) => b.writeInt32LE(v, 4 * i));
  return b;
}

function float32s(...values) {
  const b = Buffer.alloc(4 * values.length);
  values.forEach((v, i) => b.writeFloatLE(v, 4 * i));
  return b;
}

/** The bytes of an EXR holding `values` (Float32Array, width × height, row 0 the top) as one
 * FLOAT channel named `channel`. */
export function singleChannelExr(values, width, height, channel = 'Y') {
  if (values.length !== width * height) {
    throw new Error(`exr: ${values.length} values for ${width} × ${height} pixels`);
  }
  const channelList = Buffer.concat([
    Buffer.from(`${channel}\0`, 'latin1'),
    int32s(FLOAT),
    Buffer.from([0, 0, 0, 0]), // pLinear, reserved
    int32s(1, 1), // x and y sampling
    Buffer.from([0]),
  ]);
  const window = int32s(0, 0, width - 1, height - 1);
  const header = Buffer.concat([
    Buffer.from([0x76, 0x2f, 0x31, 0x01]),
    int32s(2), // version 2, single-part scanline
    attribute('channels', 'chlist', channelList),
    attribute('compression', 'compression', Buffer.from([NO_COMPRESSION])),
    attribute('dataWindow', 'box2i', window),
    attribute('displayWindow', 'box2i', window),
    attribute('lineOrder', 'lineOrder', Buffer.from([INCREASING_Y])),
    attribute('pixelAspectRatio', 'float', float32s(1)),
    attribute('screenWindowCenter', 'v2f', float32s(0, 0)),
    attribute('screenWindowWidth', 'float', float32s(1)),
    Buffer.from([0]),
  ]);
  const blockSize = 8 + 4 * width;
  const offsets = Buffer.alloc(8 * height);
  const blocks = Buffer.alloc(blockSize * height);
  const first = header.length + offsets.length;
  for (let y = 0; y < height; y++) {
    offsets.writeBigUInt64LE(BigInt(first + y * blockSize), 8 * y);
    const at = y * blockSize;
    blocks.writeInt32LE(y, at);
    blocks.writeInt32LE(4 * width, at + 4);
    for (let x = 0; x < width; x++) blocks.writeFloatLE(values[y * width + x], at + 8 + 4 * x);
  }
  return Buffer.concat([header, offsets, blocks]);
}
