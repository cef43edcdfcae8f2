// What every browser engine's render.mjs shares: its command line, a loopback server for the
// page, the view folder and the engine's packages, headless Chromium with software WebGL, and the
// EXRs written back. An engine's render.mjs names its options, its page and its packages, and
// says what one render line reports.
//
// puppeteer-core comes from the engine's own node_modules (each engine pins it in its lock
// file); a module here could not resolve it, so the engine passes it in.

import { createServer } from 'node:http';
import { readFile, writeFile, mkdtemp, rm } from 'node:fs/promises';
import { existsSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve, dirname, normalize, sep } from 'node:path';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';
import { singleChannelExr } from './exr.mjs';

const common = dirname(fileURLToPath(import.meta.url));

// SwiftShader's WebGL2 (no GPU needed), a fresh profile, nothing that reaches the network.
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

/** Prints `render.mjs: MESSAGE` and exits with 2, a usage or input error. */
export function fail(message) {
  console.error(`render.mjs: ${message}`);
  process.exit(2);
}

/** A finite number from an option's text, or a usage error naming the option. */
export function number(name, text, { integer = false, positive = false } = {}) {
  const value = Number(text);
  if (text === undefined || text.trim() === '' || !Number.isFinite(value) ||
      (integer && !Number.isInteger(value)) || (positive && value <= 0)) {
    fail(`--${name} ${text}: expected a ${positive ? 'positive ' : ''}${integer ? 'integer' : 'number'}`);
  }
  return value;
}

/** An option's value that must be one of `allowed`. */
export function oneOf(name, text, allowed) {
  if (!allowed.includes(text)) fail(`--${name} ${text}: expected one of ${allowed.join(', ')}`);
  return text;
}

/** The command line: `--view DIR --visibility OUT.exr [--depth OUT.exr]` and the engine's own
 * string options (`{ name: { type: 'string', default } }`), each taking one value. */
export function parseOptions(engineOptions) {
  // Joined as --name=value so that negative numbers (--bias -0.001) are values, not options
  // (parseArgs refuses a value that starts with a dash).
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
        'map-size': { type: 'string' },
        ...engineOptions,
      },
    }).values;
  } catch (e) {
    fail(e.message);
  }
  if (!parsed.view || !parsed.visibility) fail('--view DIR and --visibility OUT.exr are required');
  return {
    ...parsed,
    view: resolve(parsed.view),
    visibility: resolve(parsed.visibility),
    depth: parsed.depth && resolve(parsed.depth),
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

/** Serves `/` (the page), `/page.mjs`, and each of `roots` (URL prefix → folder; this folder is
 * `/common/`), on loopback only. */
function serve(pageHtml, pageScript, roots) {
  const folders = { ...roots, '/common/': common };
  const server = createServer(async (req, res) => {
    const path = decodeURIComponent(new URL(req.url, 'http://localhost').pathname);
    if (path === '/') return res.writeHead(200, { 'content-type': 'text/html' }).end(pageHtml);
    if (path === '/page.mjs') return res.writeHead(200, { 'content-type': 'text/javascript' }).end(pageScript);
    for (const [prefix, root] of Object.entries(folders)) {
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

function decodeF32(text) {
  return new Float32Array(Buffer.from(text, 'base64').buffer.slice(0));
}

/**
 * Renders `opts.view` (a view-export folder) in the engine's page and writes the visibility and,
 * when asked, the depth EXR. The page defines `window.renderView(view, settings)`, which returns
 * `{ visibility, depth }` as base64 f32 rows from the top, and whatever else the engine reports.
 *
 * - `puppeteer`: the engine's puppeteer-core.
 * - `pageFile`: the page module's path; `importMap`: the page's import map (an object).
 * - `roots`: URL prefix → folder, the engine's packages; the view is served under `/view/`.
 * - `settings(view)`: what the page gets beside the view.
 *
 * Returns `{ view, settings, result }`: the page's result, for the engine's timing line.
 */
export async function renderInChromium({ puppeteer, opts, pageFile, importMap, roots, settings }) {
  const view = JSON.parse(await readFile(join(opts.view, 'view.json'), 'utf8'));
  if (view.format !== 'shadowtruth/view/v1') fail(`${opts.view}/view.json: format ${view.format}, expected shadowtruth/view/v1`);
  const pageHtml = `<!doctype html><html><head><meta charset="utf-8">
<script type="importmap">${JSON.stringify({ imports: importMap })}</script>
<script type="module" src="/page.mjs"></script></head><body></body></html>`;
  const server = await serve(pageHtml, await readFile(pageFile, 'utf8'), { ...roots, '/view/': opts.view });
  const profile = await mkdtemp(join(tmpdir(), 'shadowtruth-chromium-'));
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
    await page.goto(`http://127.0.0.1:${server.address().port}/`);
    try {
      await Promise.race([page.waitForFunction('window.renderView !== undefined', { timeout: 60000 }), pageFailed]);
    } catch (e) {
      fail(`the page did not load: ${e}\n${logs.join('\n')}`);
    }
    const pageSettings = settings(view);
    const result = await page.evaluate(async (v, s) => {
      try {
        return await window.renderView(v, s);
      } catch (e) {
        return { error: `${e}\n${e.stack}` };
      }
    }, view, pageSettings);
    if (result.error) fail(`the page failed: ${result.error}\n${logs.join('\n')}`);
    const { width, height } = view.camera;
    await writeFile(opts.visibility, singleChannelExr(decodeF32(result.visibility), width, height));
    if (opts.depth) await writeFile(opts.depth, singleChannelExr(decodeF32(result.depth), width, height));
    return { view, settings: pageSettings, result };
  } finally {
    await browser?.close();
    server.close();
    await rm(profile, { recursive: true, force: true });
  }
}

/** The render line's tail: the page's times and the engine's warnings. */
export function timings(engine, result) {
  return (
    `rendered in ${result.renderMs.toFixed(0)} ms (visibility ${result.visibilityMs.toFixed(0)} ms, ` +
    `depth ${result.depthMs.toFixed(0)} ms)` +
    (result.warnings.length ? `; ${engine} warned: ${result.warnings.join(' | ')}` : '')
  );
}
