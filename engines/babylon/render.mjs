// Renders an exported view (`shadowtruth view-export`) with Babylon.js's own shadow maps in
// headless Chromium and writes what shadowtruth scores: the light's shadow factor per camera
// pixel (visibility EXR) and, optionally, the distance from the camera to the surface (depth EXR).
//
// Usage: node engines/babylon/render.mjs --view DIR --visibility OUT.exr [--depth OUT.exr]
//          [--filter none|poisson|pcf|pcss|esm|blur-esm|close-esm|blur-close-esm|contact-hardening]
//          [--pcf-quality low|medium|high] [--bias X] [--normal-bias X] [--depth-scale X]
//          [--map-size N] [--map-type float16|float32] [--cascades N] [--lambda X]
//          [--stabilize-cascades false|true]
// Unset options keep Babylon's defaults: the ShadowGenerator's (filter none, quality high, bias
// 0.00005, normalBias 0, depthScale the light's: 50), or with `--cascades N` (directional lights)
// the CascadedShadowGenerator's (filter pcf, lambda 0.5, cascades not stabilized, the map fitted
// to the camera's frustum instead of the exported box); the map size defaults to view.json's
// shadow-map resolution. Babylon stores the map as half floats where the device renders and
// filters them, float32 only when asked (`--map-type float32`, the generator's `useFullFloatFirst`).

import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';
import { parseOptions, number, oneOf, renderInChromium, timings, fail } from '../common/harness.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const FILTERS = ['none', 'poisson', 'pcf', 'pcss', 'esm', 'blur-esm', 'close-esm', 'blur-close-esm', 'contact-hardening'];
/** Babylon's CascadedShadowGenerator draws 2 to 4 cascades (its `numCascades` setter clamps to
 * MIN_CASCADES_COUNT and MAX_CASCADES_COUNT): another count is refused, not changed silently. */
const MIN_CASCADES = 2;
const MAX_CASCADES = 4;

const opts = parseOptions({
  filter: { type: 'string' },
  'pcf-quality': { type: 'string', default: 'high' },
  bias: { type: 'string' },
  'normal-bias': { type: 'string' },
  'depth-scale': { type: 'string' },
  'map-type': { type: 'string', default: 'float16' },
  cascades: { type: 'string' },
  lambda: { type: 'string' },
  'stabilize-cascades': { type: 'string' },
});
const optional = (name, how) => (opts[name] !== undefined ? number(name, opts[name], how) : undefined);
const cascades = optional('cascades', { integer: true, positive: true });
if (cascades !== undefined && !(cascades >= MIN_CASCADES && cascades <= MAX_CASCADES)) {
  fail(`--cascades ${cascades}: Babylon.js draws ${MIN_CASCADES} to ${MAX_CASCADES} cascades`);
}
const lambda = optional('lambda');
if (lambda !== undefined && !(lambda >= 0 && lambda <= 1)) fail(`--lambda ${lambda}: expected a number from 0 to 1`);
const stabilize = opts['stabilize-cascades'] && oneOf('stabilize-cascades', opts['stabilize-cascades'], ['false', 'true']) === 'true';
if (cascades === undefined && (lambda !== undefined || stabilize !== undefined)) {
  fail('--lambda and --stabilize-cascades are settings of the cascaded generator: give --cascades N');
}
const filter = opts.filter && oneOf('filter', opts.filter, FILTERS);

const { view, settings, result } = await renderInChromium({
  puppeteer,
  opts,
  pageFile: join(here, 'page.mjs'),
  importMap: {
    '@babylonjs/core': '/babylonjs/core/index.js',
    '@babylonjs/core/': '/babylonjs/core/',
    '@babylonjs/loaders/': '/babylonjs/loaders/',
  },
  roots: { '/babylonjs/': join(here, 'node_modules', '@babylonjs') },
  settings: (v) => {
    if (cascades !== undefined && v.light.type !== 'directional') {
      fail(`--cascades: ${v.light.type} light; Babylon.js cascades directional lights only`);
    }
    return {
      filter,
      pcfQuality: oneOf('pcf-quality', opts['pcf-quality'], ['low', 'medium', 'high']),
      float32: oneOf('map-type', opts['map-type'], ['float16', 'float32']) === 'float32',
      bias: optional('bias'),
      normalBias: optional('normal-bias'),
      depthScale: optional('depth-scale', { positive: true }),
      mapSize: opts.mapSize ?? v.light.shadow_map.resolution,
      cascades,
      lambda,
      stabilize,
    };
  },
});
const { width, height } = view.camera;
console.error(
  `Babylon.js ${result.version} ${result.generator} filter ${result.filter} map ${settings.mapSize}² ${result.mapType} ` +
    `bias ${result.bias} normalBias ${result.normalBias} depthScale ${result.depthScale}: ${width}×${height} ` +
    timings('Babylon.js', result),
);
