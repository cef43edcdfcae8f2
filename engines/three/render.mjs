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

import { createServer } from 'node:http';
import { readFile, writeFile, mkdtemp, rm } from 'node:fs/promises';
import { existsSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve, dirname, normalize, sep } from 'node:path';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';
import puppeteer from 'puppeteer-core';
import { singleChannelExr } from './exr.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const threeRoot = join(here, 'node_modules', 'three');

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
        'shadow-type': { type: 'string', default: 'pcf' },
        bias: { type: 'string', default: '0' },
        'normal-bias': { type: 'string', default: '0' },
        radius: { type: 'string', default: '1' },
        'blur-samples': { type: 'string', default: '8' },
        'map-size': { type: 'string' },
      },
    }).values;
  } catch (e) {
    fail(e.message);
  }
  if (!parsed.view || !parsed.visibility) fail('--view DIR and --visibility OUT.exr are required');
  const types = { basic: 'BasicShadowMap', pcf: 'PCFShadowMap', pcfsoft: 'PCFSoftShadowMap', vsm: 'VSMShadowMap' };
  const shadowType = types[parsed['shadow-type']];
  if (!shadowType) fail(`--shadow-type ${parsed['shadow-type']}: expected one of ${Object.keys(types).join(', ')}`);
  return {
    view: resolve(parsed.view),
    visibility: resolve(parsed.visibility),
    depth: parsed.depth && resolve(parsed.depth),
    shadowType,
    bias: number('bias', parsed.bias),
    normalBias: number('normal-bias', parsed['normal-bias']),
    radius: number('radius', parsed.radius),
    blurSamples: number('blur-samples', parsed['blur-samples'], { integer: true, positive: true }),
    mapSize: parsed['map-size'] && number('map-size', parsed['map-size'], { integer: true, positive: true }),
  };
}

function chromiumPath() {
  const candidates = [process.env.CHROMIUM, '/usr/bin/chromium', '/usr/bin/chromium-browser', '/usr/bin/google-chrome'];
  const found = candidates.find((p) => p && existsSync(p));
  if (!found) fail('no Chromium found: install it (`apt-get install chromium`) or set CHROMIUM to its path');
  return found;
}

const TYPES = { '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json', '.html': 'text/html' };

/** Serves the page, its module, the view folder under /view/ and three's package under /three/,
 * on loopback only. */
function serve(viewDir, pageScript) {
  const roots = { '/view/': viewDir, '/three/': threeRoot };
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
<script type="importmap">{ "imports": { "three": "/three/build/three.module.js", "three/addons/": "/three/examples/jsm/" } }</script>
<script type="module" src="/page.mjs"></script></head><body></body></html>`;

async function main() {
  const opts = options();
  const view = JSON.parse(await readFile(join(opts.view, 'view.json'), 'utf8'));
  if (view.format !== 'shadowtruth/view/v1') fail(`${opts.view}/view.json: format ${view.format}, expected shadowtruth/view/v1`);
  const pageScript = await readFile(join(here, 'page.mjs'), 'utf8');
  const server = await serve(opts.view, pageScript);
  const port = server.address().port;
  const profile = await mkdtemp(join(tmpdir(), 'shadowtruth-three-'));
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
      shadowType: opts.shadowType,
      bias: opts.bias,
      normalBias: opts.normalBias,
      radius: opts.radius,
      blurSamples: opts.blurSamples,
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
      `three.js r${result.revision} ${opts.shadowType} map ${settings.mapSize}² bias ${opts.bias} normalBias ` +
        `${opts.normalBias}: ${width}×${height} rendered in ${result.renderMs.toFixed(0)} ms ` +
        `(visibility ${result.visibilityMs.toFixed(0)} ms, depth ${result.depthMs.toFixed(0)} ms)` +
        (result.warnings.length ? `; three.js warned: ${result.warnings.join(' | ')}` : ''),
    );
  } finally {
    await browser?.close();
    server.close();
    await rm(profile, { recursive: true, force: true });
  }
}

await main();
