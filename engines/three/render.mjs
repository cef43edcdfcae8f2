// Renders an exported view (`shadowtruth view-export`) with three.js's own shadow maps in
// headless Chromium and writes what shadowtruth scores: the light's shadow factor per camera
// pixel (visibility EXR) and, optionally, the distance from the camera to the surface (depth EXR).
//
// Usage: node engines/three/render.mjs --view DIR --visibility OUT.exr [--depth OUT.exr]
//          [--shadow-type basic|pcf|pcfsoft|vsm] [--bias X] [--normal-bias X] [--radius X]
//          [--blur-samples N] [--map-size N]
// Unset options keep three.js's defaults (PCFShadowMap, bias 0, normalBias 0, radius 1,
// blurSamples 8); the map size defaults to view.json's shadow-map resolution. three.js r187 has
// removed PCFSoftShadowMap: `pcfsoft` is passed on, and three warns and renders PCF (the warning
// is printed on the timing line).

import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';
import { parseOptions, number, oneOf, renderInChromium, timings } from '../common/harness.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const SHADOW_TYPES = { basic: 'BasicShadowMap', pcf: 'PCFShadowMap', pcfsoft: 'PCFSoftShadowMap', vsm: 'VSMShadowMap' };

const opts = parseOptions({
  'shadow-type': { type: 'string', default: 'pcf' },
  bias: { type: 'string', default: '0' },
  'normal-bias': { type: 'string', default: '0' },
  radius: { type: 'string', default: '1' },
  'blur-samples': { type: 'string', default: '8' },
});
const shadowType = SHADOW_TYPES[oneOf('shadow-type', opts['shadow-type'], Object.keys(SHADOW_TYPES))];
const bias = number('bias', opts.bias);
const normalBias = number('normal-bias', opts['normal-bias']);
const radius = number('radius', opts.radius);
const blurSamples = number('blur-samples', opts['blur-samples'], { integer: true, positive: true });

const { view, settings, result } = await renderInChromium({
  puppeteer,
  opts,
  pageFile: join(here, 'page.mjs'),
  importMap: { three: '/three/build/three.module.js', 'three/addons/': '/three/examples/jsm/' },
  roots: { '/three/': join(here, 'node_modules', 'three') },
  settings: (v) => ({ shadowType, bias, normalBias, radius, blurSamples, mapSize: opts.mapSize ?? v.light.shadow_map.resolution }),
});
const { width, height } = view.camera;
console.error(
  `three.js r${result.revision} ${shadowType} map ${settings.mapSize}² bias ${bias} normalBias ${normalBias}: ` +
    `${width}×${height} ${timings('three.js', result)}`,
);
