// What every engine's page shares (served as /common/page_util.mjs): the engine's warnings, kept
// for the render line, and the float read-back turned into rows from the top, sent back as
// base64 f32.

/** Every console.warn from here on, in order (the engines warn about settings they ignore). */
export function captureWarnings() {
  const warnings = [];
  const originalWarn = console.warn;
  console.warn = (...args) => {
    warnings.push(args.join(' '));
    originalWarn(...args);
  };
  return warnings;
}

/** The red channel of a WebGL read-back (RGBA f32, rows from the bottom) as rows from the top;
 * pixels of alpha 0 (nothing drawn: the cleared background) get `fill`. */
export function rowsFromTop(rgba, width, height, fill) {
  const out = new Float32Array(width * height);
  for (let y = 0; y < height; y++) {
    const src = (height - 1 - y) * width;
    for (let x = 0; x < width; x++) {
      const i = 4 * (src + x);
      out[y * width + x] = rgba[i + 3] === 0 ? fill : rgba[i];
    }
  }
  return out;
}

/** An f32 array as base64, the one form page.evaluate returns compactly. */
export function base64(f32) {
  const bytes = new Uint8Array(f32.buffer);
  let text = '';
  for (let i = 0; i < bytes.length; i += 0x8000) text += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(text);
}
