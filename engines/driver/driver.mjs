// The engine driver (docs/engines.md): one headless Chromium, started once
// and reused by every cell, driven through the DevTools protocol by
// puppeteer-core. The harness (harness/engine/engine.c) starts this script,
// writes one request a line on its stdin and reads one reply a line on its
// stdout; nothing else goes to stdout.
//
// A request: {"id", "engine", "scene", "width", "height", "light",
//   "technique", "params", "map_size", "warmup", "frames", "outputs",
//   "output"}, where "light" is {"kind" (spot, directional), "eye", "x", "y",
//   "z" (the light's frame: it looks along -z, y up), "near", "far",
//   "window" (l, r, b, t at the near plane: shadowbench's fitted frustum),
//   "shape" (rect, disk, sun), "size" (a rect's [w, h]), "radius" (a
//   disk's), "half_angle" (the sun's, radians), "size_uv" (the light's
//   size in shadow-map UV at the near plane; the sun's: per world unit of
//   depth), "cone_tan" (a spot's: the tangent of the smallest cone about
//   its axis holding the scene inside the window), "view_far" (the
//   farthest view depth the camera sees)}; the reply: {"id", "ok": true,
//   "engine", "version", "renderer", "ms": [...], "texel_ratio" (optional:
//   [x, y], the engine's map's texel over shadowbench's at the same map
//   size), "notice" (optional: one line on what the numbers do not show)}
//   once the outputs are in the file "output" (float32, each output W x H,
//   top row first, in the order asked), or {"id", "ok": false, "error":
//   "one line"}.
//
// Chromium is launched with its DevTools pipe (no port): when this process
// ends, however it ends, the pipe closes and Chromium exits with it.
import fs from 'node:fs';
import path from 'node:path';
import readline from 'node:readline';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

// argv: chromium, the harness's folder for the browser's profile, the adapters' folder.
const ENGINES_DIR = process.argv[4] ? path.resolve(process.argv[4])
                                    : path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const ORIGIN = 'http://shadowbench.invalid';
const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json',
                '.gltf': 'model/gltf+json', '.bin': 'application/octet-stream', '.wasm': 'application/wasm',
                '.png': 'image/png', '.jpg': 'image/jpeg' };

const say = (reply) => process.stdout.write(JSON.stringify(reply) + '\n');
const oneLine = (e) => String(e && e.message ? e.message : e).split('\n')[0].slice(0, 400);

let browser = null;
const pages = new Map();  // engine -> { page, errors: [] }
const sceneDirs = new Map();  // token -> folder of a scene file

// Serves the engines' folder and the scenes' folders to the page from
// one origin (ES modules do not load from file://).
function serve(request) {
    const url = new URL(request.url());
    if (url.origin !== ORIGIN)
        return request.abort();
    let file = null;
    const parts = decodeURIComponent(url.pathname).split('/').filter(Boolean);
    if (parts[0] === 'engines')
        file = path.join(ENGINES_DIR, ...parts.slice(1));
    else if (parts[0] === 'scene' && sceneDirs.has(parts[1]))
        file = path.join(sceneDirs.get(parts[1]), ...parts.slice(2));
    const root = parts[0] === 'engines' ? ENGINES_DIR : sceneDirs.get(parts[1]);
    if (!file || !root || path.relative(root, file).startsWith('..') || !fs.existsSync(file) ||
        !fs.statSync(file).isFile())
        return request.respond({ status: 404, contentType: 'text/plain', body: 'not found' });
    request.respond({ status: 200, contentType: TYPES[path.extname(file)] || 'application/octet-stream',
                      body: fs.readFileSync(file) });
}

async function launch(executable, folder) {
    browser = await puppeteer.launch({
        executablePath: executable,
        userDataDir: folder ? path.join(folder, 'profile') : undefined,
        pipe: true,
        headless: true,
        handleSIGINT: false, handleSIGTERM: false, handleSIGHUP: false,
        protocolTimeout: 0,
        args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-gpu-sandbox',
               '--ignore-gpu-blocklist', '--disable-background-timer-throttling', '--mute-audio',
               '--no-first-run', '--no-default-browser-check', '--disable-extensions'],
    });
}

async function pageFor(engine) {
    if (pages.has(engine))
        return pages.get(engine);
    const entry = { page: await browser.newPage(), errors: [] };
    const { page } = entry;
    page.on('pageerror', (e) => entry.errors.push(oneLine(e)));
    page.on('console', (m) => {  /* a failed load is said by its response, with its address */
        if (m.type() === 'error' && !m.text().startsWith('Failed to load resource'))
            entry.errors.push(oneLine(m.text()));
    });
    page.on('response', (r) => { if (r.status() >= 400) entry.errors.push(`${r.url()}: HTTP ${r.status()}`); });
    page.on('requestfailed', (r) => entry.errors.push(`${r.url()}: ${r.failure() ? r.failure().errorText : 'failed'}`));
    await page.setRequestInterception(true);
    page.on('request', serve);
    const adapter = path.join(ENGINES_DIR, engine, 'page.html');
    if (!/^[a-z0-9_]+$/.test(engine) || !fs.existsSync(adapter))
        throw new Error(`no adapter ${path.relative(process.cwd(), adapter)}`);
    await page.goto(`${ORIGIN}/engines/${engine}/page.html`);
    await page.waitForFunction('window.sbReady !== undefined', { timeout: 0 });  /* the harness's limit */
    const ready = await page.evaluate('window.sbReady');
    if (ready !== true)
        throw new Error(`failed to load: ${ready}`);
    if (entry.errors.length)
        throw new Error(`failed to load: ${entry.errors[0]}`);
    pages.set(engine, entry);
    return entry;
}

async function handle(req) {
    const entry = await pageFor(req.engine);
    entry.errors.length = 0;
    const dir = path.dirname(path.resolve(req.scene));
    const token = Buffer.from(dir).toString('hex').slice(-32) + String(sceneDirs.size);
    let found = [...sceneDirs].find(([, d]) => d === dir);
    if (!found) {
        sceneDirs.set(token, dir);
        found = [token, dir];
    }
    const sceneUrl = `${ORIGIN}/scene/${found[0]}/${encodeURIComponent(path.basename(req.scene))}`;
    const out = await entry.page.evaluate((r, url) => window.sbRender({ ...r, sceneUrl: url }), req, sceneUrl);
    if (entry.errors.length)
        throw new Error(`page error: ${entry.errors[0]}`);
    const bytes = Buffer.from(out.data, 'base64');
    if (bytes.length !== 4 * req.width * req.height * req.outputs.length)
        throw new Error(`an image of the wrong size: the page returned ${bytes.length} bytes, not ` +
                        `${req.outputs.length} image(s) of ${req.width}x${req.height} float32`);
    const tmp = `${req.output}.tmp.${process.pid}`;
    fs.writeFileSync(tmp, bytes);
    fs.renameSync(tmp, req.output);
    return { id: req.id, ok: true, engine: req.engine, version: out.version, renderer: out.renderer, ms: out.ms,
             texel_ratio: out.texel_ratio, notice: out.notice };
}

async function main() {
    const executable = process.argv[2] || '/usr/bin/chromium';
    try {
        await launch(executable, process.argv[3]);
    } catch (e) {
        say({ id: 0, ok: false, error: `chromium (${executable}) did not start: ${oneLine(e)}` });
        process.exit(1);
    }
    /* the browser's pid: puppeteer starts it in a session of its own, which the harness kills too */
    say({ id: 0, ok: true, version: await browser.version(), pid: browser.process().pid });
    const lines = readline.createInterface({ input: process.stdin });
    let queue = Promise.resolve();
    lines.on('line', (line) => {
        queue = queue.then(async () => {
            let req = null;
            try {
                req = JSON.parse(line);
                say(await handle(req));
            } catch (e) {
                say({ id: req && req.id, ok: false, error: oneLine(e) });
            }
        });
    });
    lines.on('close', () => queue.then(() => browser.close()).finally(() => process.exit(0)));
}

main();
