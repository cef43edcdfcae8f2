// Renders an exported view (`shadowtruth view-export`) with Babylon.js's own shadow maps in
// headless Chromium and writes what shadowtruth scores: the light's shadow factor per camera
// pixel (visibility EXR) and, optionally, the distance from the camera to the surface (depth EXR).
//
// Usage: node engines/babylon/render.mjs --view DIR --visibility OUT.exr [--depth OUT.exr]
//          [--filter none|poisson|pcf|pcss|esm|blur-esm|close-esm|blur-close-esm|contact-hardening]
//          [--pcf-quality low|medium|high] [--bias X] [--normal-bias X] [--depth-scale X]
//          [--map-size N] [--map-type float16|float32]
// Unset options keep Babylon's ShadowGenerator defaults (filter none, quality high, bias 0.00005,
// normalBias 0, depthScale the light's: 50); the map size defaults to view.json's shadow-map
// resolution. Babylon stores the map as half floats where the device renders and filters them,
// float32 only when asked (`--map-type float32`, the generator's `useFullFloatFirst`).

import { createServer } from 'node:http';
import { readFile, writeFile, mkdtemp, rm } from 'node:fs/promises';
import { existsSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve, dirname, normalize, sep } from 'node:path';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';
import puppeteer from 'puppeteer-core';
import { singleChannelExr } from '../three/exr.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const babylonRoot = join(here, 'node_modules', '@babylonjs');

const CHROMIUM_FLAGS = [
  '--headless',
  '--no-sandbox',
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--ignore-gpu-blocklist',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--no-first-run',
  '--disable-quic',
];

function fail(message) {
  console.error(`render.mjs: ${message}`);
  process.exit(2);
}

function number(name, text, { integer = false, positive = false } = {}) {
  const value = Number(text);
  if (text === undefined || text.trim() === '' || !Number.isFinite(value) ||
      (integer && !Number.isInteger(value)) || (positive && value <= 0)) {
    fail(`--${name} ${text}: expected a ${positive ? 'positive ' : ''}${integer ? 'integer' : 'number'}`);
  }
  return value;
}

function options() {
  // Every option takes a value; joined as --name=value so that negative numbers (--bias -0.001)
  // are values, not options (parseArgs refuses a value that starts with a dash).
  const args = [];
  const argv = process.argv.slice(2);
  for (let i = 0; i < argv.length; i++) {
    if (argv[i].startsWith('--') && !argv[i].includes('=') && i + 1 < argv.length) args.push(`${argv[i]}=${argv[++i]}`);
    else args.push(argv[i]);
  }
  let parsed;
  try {
    parsed = parseArgs({
      args,
      options: {
        view: { type: 'string' },
        visibility: { type: 'string' },
        depth: { type: 'string' },
        filter: { type: 'string', default: 'none' },
        'pcf-quality': { type: 'string', default: 'high' },
        bias: { type: 'string' },
        'normal-bias': { type: 'string' },
        'depth-scale': { type: 'string' },
        'map-size': { type: 'string' },
        'map-type': { type: 'string', default: 'float16' },
      },
    }).values;
  } catch (e) {
    fail(e.message);
  }
  if (!parsed.view || !parsed.visibility) fail('--view DIR and --visibility OUT.exr are required');
  const one = (name, allowed) => {
    if (!allowed.includes(parsed[name])) fail(`--${name} ${parsed[name]}: expected one of ${allowed.join(', ')}`);
    return parsed[name];
  };
  const optional = (name, how) => parsed[name] !== undefined ? number(name, parsed[name], how) : undefined;
  return {
    view: resolve(parsed.view),
    visibility: resolve(parsed.visibility),
    depth: parsed.depth && resolve(parsed.depth),
    filter: one('filter', ['none', 'poisson', 'pcf', 'pcss', 'esm', 'blur-esm', 'close-esm', 'blur-close-esm', 'contact-hardening']),
    pcfQuality: one('pcf-quality', ['low', 'medium', 'high']),
    float32: one('map-type', ['float16', 'float32']) === 'float32',
    bias: optional('bias'),
    normalBias: optional('normal-bias'),
    depthScale: optional('depth-scale', { positive: true }),
    mapSize: optional('map-size', { integer: true, positive: true }),
  };
}

function chromiumPath() {
  const candidates = [process.env.CHROMIUM, '/usr/bin/chromium', '/usr/bin/chromium-browser', '/usr/bin/google-chrome'];
  const found = candidates.find((p) => p && existsSync(p));
  if (!found) fail('no Chromium found: install it (`apt-get install chromium`) or set CHROMIUM to its path');
  return found;
}

const TYPES = { '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json', '.html': 'text/html' };

/** Serves the page, its module, the view folder under /view/ and Babylon's packages under
 * /babylonjs/, on loopback only. */
function serve(viewDir, pageScript) {
  const roots = { '/view/': viewDir, '/babylonjs/': babylonRoot };
  const server = createServer(async (req, res) => {
    const path = decodeURIComponent(new URL(req.url, 'http://localhost').pathname);
    if (path === '/') return res.writeHead(200, { 'content-type': 'text/html' }).end(PAGE);
    if (path === '/page.mjs') return res.writeHead(200, { 'content-type': 'text/javascript' }).end(pageScript);
    for (const [prefix, root] of Object.entries(roots)) {
      if (!path.startsWith(prefix)) continue;
      const file = normalize(join(root, path.slice(prefix.length)));
      // Only files inside the served folder.
      if (!file.startsWith(root + sep)) break;
      try {
        const body = await readFile(file);
        const type = TYPES[file.slice(file.lastIndexOf('.'))] ?? 'application/octet-stream';
        return res.writeHead(200, { 'content-type': type }).end(body);
      } catch {
        return res.writeHead(404).end();
      }
    }
    res.writeHead(404).end();
  });
  return new Promise((ok) => server.listen(0, '127.0.0.1', () => ok(server)));
}

const PAGE = `<!doctype html><html><head><meta charset="utf-8">
<script type="importmap">{ "imports": { "@babylonjs/core": "/babylonjs/core/index.js", "@babylonjs/core/": "/babylonjs/core/", "@babylonjs/loaders/": "/babylonjs/loaders/" } }</script>
<script type="module" src="/page.mjs"></script></head><body></body></html>`;

async function main() {
  const opts = options();
  const view = JSON.parse(await readFile(join(opts.view, 'view.json'), 'utf8'));
  if (view.format !== 'shadowtruth/view/v1') fail(`${opts.view}/view.json: format ${view.format}, expected shadowtruth/view/v1`);
  const pageScript = await readFile(join(here, 'page.mjs'), 'utf8');
  const server = await serve(opts.view, pageScript);
  const port = server.address().port;
  const profile = await mkdtemp(join(tmpdir(), 'shadowtruth-babylon-'));
  let browser;
  try {
    browser = await puppeteer.launch({
      executablePath: chromiumPath(),
      headless: true,
      args: [...CHROMIUM_FLAGS, `--user-data-dir=${profile}`],
    });
    const page = await browser.newPage();
    const logs = [];
    page.on('console', (m) => logs.push(m.text()));
    // A page that cannot load (a missing module, a syntax error) fails at once, not at the timeout.
    const pageFailed = new Promise((_, reject) => page.on('pageerror', (e) => reject(e)));
    pageFailed.catch(() => {});
    await page.goto(`http://127.0.0.1:${port}/`);
    try {
      await Promise.race([page.waitForFunction('window.renderView !== undefined', { timeout: 60000 }), pageFailed]);
    } catch (e) {
      fail(`the page did not load: ${e}\n${logs.join('\n')}`);
    }
    const settings = {
      filter: opts.filter,
      pcfQuality: opts.pcfQuality,
      float32: opts.float32,
      bias: opts.bias,
      normalBias: opts.normalBias,
      depthScale: opts.depthScale,
      mapSize: opts.mapSize ?? view.light.shadow_map.resolution,
    };
    const result = await page.evaluate(async (v, s) => {
      try {
        return await window.renderView(v, s);
      } catch (e) {
        return { error: `${e}\n${e.stack}` };
      }
    }, view, settings);
    if (result.error) fail(`the page failed: ${result.error}\n${logs.join('\n')}`);
    const { width, height } = view.camera;
    const visibility = new Float32Array(Buffer.from(result.visibility, 'base64').buffer.slice(0));
    await writeFile(opts.visibility, singleChannelExr(visibility, width, height));
    if (opts.depth) {
      const depth = new Float32Array(Buffer.from(result.depth, 'base64').buffer.slice(0));
      await writeFile(opts.depth, singleChannelExr(depth, width, height));
    }
    console.error(
      `Babylon.js ${result.version} filter ${opts.filter} map ${settings.mapSize}² ${result.mapType} bias ${result.bias} ` +
        `normalBias ${result.normalBias} depthScale ${result.depthScale}: ${width}×${height} rendered in ` +
        `${result.renderMs.toFixed(0)} ms (visibility ${result.visibilityMs.toFixed(0)} ms, depth ${result.depthMs.toFixed(0)} ms)` +
        (result.warnings.length ? `; Babylon.js warned: ${result.warnings.join(' | ')}` : ''),
    );
  } finally {
    await browser?.close();
    server.close();
    await rm(profile, { recursive: true, force: true });
  }
}

await main();
