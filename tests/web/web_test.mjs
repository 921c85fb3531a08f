// The viewer page in a real browser (docs/web.md): Debian's chromium,
// headless, WebGL through ANGLE on SwiftShader, driven by puppeteer-core.
// Run by tests/web/run.sh (`make web-test`), which builds the page first.
//
//   node tests/web/web_test.mjs --page build-web/web --parallax build/parallax --out out/web
//        [--screenshot docs/web-viewer.png] [--shader-table docs/web-shaders.md] [--webgl 2,1]
//
// For each WebGL version:
//   1. the page as a person uses it, with no console message of any kind:
//      the first scene drawn, a mouse orbit, a wheel dolly, a technique and
//      sample-count switch, a scene folder opened from files (a real material
//      with a JPEG albedo), a broken scene refused with its JSON path while
//      the last scene stays, a folder of several .json files (the scene
//      chosen from the list), an ASTC file refused by name, the hit-error overlay, and (WebGL 2) a phone's
//      viewport with a one-finger orbit, and a browser without WebGL 2
//      (the page falls back to WebGL 1 and says so);
//   2. every shader variant compiled and linked under ANGLE;
//   3. each golden scene drawn in the page and compared with the native
//      golden (`parallax compare`, tests/web/tolerances.json);
//   4. frame times per technique (a report, never asserted).
// Writes out/web/report.json and report.md; exits 1 naming each failure.
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { execFileSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, '../..');
const args = Object.fromEntries(process.argv.slice(2).reduce((acc, a, i, all) => {
  if (a.startsWith('--')) acc.push([a.slice(2), all[i + 1] && !all[i + 1].startsWith('--') ? all[i + 1] : 'true']);
  return acc;
}, []));
const pageDir = path.resolve(args.page || 'build-web/web');
const parallax = path.resolve(args.parallax || 'build/parallax');
const outDir = path.resolve(args.out || 'out/web');
const versions = (args.webgl || '2,1').split(',').map(Number);
const chromium = process.env.CHROMIUM || '/usr/bin/chromium';
for (const [what, p] of [['the page (make web)', path.join(pageDir, 'parallax_viewer.wasm')], ['parallax (make build)', parallax], ['chromium', chromium]]) {
  if (!fs.existsSync(p)) { console.error(`web test: ${what} is missing: ${p}`); process.exit(2); }
}
fs.mkdirSync(outDir, { recursive: true });
const tolerances = JSON.parse(fs.readFileSync(path.join(here, 'tolerances.json'), 'utf8'));

const failures = [];
const fail = (m) => { failures.push(m); console.log(`  FAIL ${m}`); };
const check = (cond, m) => { if (!cond) fail(m); return cond; };

// --- the page, served from 127.0.0.1 only -----------------------------------
const types = { '.html': 'text/html', '.js': 'text/javascript', '.wasm': 'application/wasm', '.css': 'text/css' };
const server = http.createServer((req, res) => {
  const url = new URL(req.url, 'http://127.0.0.1');
  const file = path.normalize(path.join(pageDir, decodeURIComponent(url.pathname)));
  if (!file.startsWith(pageDir + path.sep)) { res.writeHead(403); res.end(); return; }
  fs.readFile(file, (e, data) => {
    if (e) { res.writeHead(404); res.end(); return; }
    res.writeHead(200, { 'Content-Type': types[path.extname(file)] || 'application/octet-stream', 'Cache-Control': 'no-store' });
    res.end(data);
  });
});
await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
const base = `http://127.0.0.1:${server.address().port}/index.html`;

const browser = await puppeteer.launch({
  executablePath: chromium,
  headless: true,
  args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--no-sandbox', '--no-first-run'],
  protocolTimeout: 600000,
});

// A page with every console message, page error and failed request kept.
async function openPage(query, viewport) {
  const page = await browser.newPage();
  const messages = [];
  page.on('console', (m) => messages.push(`${m.type()}: ${m.text()}`));
  page.on('pageerror', (e) => messages.push(`page error: ${e.message}`));
  page.on('requestfailed', (r) => messages.push(`request failed: ${r.url()}`));
  await page.setViewport(viewport || { width: 1100, height: 720 });
  await page.goto(`${base}?${query}`, { waitUntil: 'load' });
  await page.evaluate(() => window.parallaxReady);
  await settle(page);
  return { page, messages };
}
// Lets requestAnimationFrame draw what the last action changed.
const settle = (page) => page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok))));
const camera = (page) => page.evaluate(() => window.parallax.camera());
const distance = (c) => Math.hypot(...c.position.map((p, i) => p - c.target[i]));
const canvasShot = async (page) => (await page.$('#canvas')).screenshot();
const errorText = (page) => page.$eval('#error', (e) => (e.hidden ? '' : e.textContent));

const report = { chromium: (await browser.version()), versions: {} };

async function useThePage(webgl, r) {
  const { page, messages } = await openPage(`webgl=${webgl}&scene=showcase`);
  const ctx = await page.evaluate(() => window.parallax.context());
  r.context = { version: ctx.version, glsl: ctx.glsl_version, renderer: ctx.renderer, fragment_highp: ctx.fragment_highp,
    mediump: ctx.fragment_mediump_float, highp: ctx.fragment_highp_float, float_capture: ctx.float_capture,
    compressed_formats: ctx.compressed_formats, extensions: ctx.extensions.filter((e) => !e.startsWith('GL_')) };
  check(ctx.webgl === webgl, `WebGL ${webgl}: the page made WebGL ${ctx.webgl} (${ctx.fallback})`);
  check(ctx.es_major === (webgl === 2 ? 3 : 2), `WebGL ${webgl}: drawn on the ES ${ctx.es_major} paths`);
  const plan = await page.evaluate(() => window.parallax.report());
  check(plan.length > 0, `WebGL ${webgl}: the first scene drew no object`);
  check((await errorText(page)) === '', `WebGL ${webgl}: error shown at start: ${await errorText(page)}`);
  if (webgl === 2 && args.screenshot) {
    // A few frames first, so that the corner's median is not the first frame's compile.
    for (let i = 0; i < 6; i++) { await page.evaluate(() => window.dispatchEvent(new Event('resize'))); await settle(page); }
    await page.screenshot({ path: args.screenshot });
    console.log(`  wrote ${args.screenshot}`);
  }

  // Orbit with the mouse: the camera turns about its target, the image changes.
  const box = await (await page.$('#canvas')).boundingBox();
  const before = await camera(page), shotBefore = await canvasShot(page);
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 120, box.y + box.height / 2 + 30, { steps: 6 });
  await page.mouse.up();
  await settle(page);
  const after = await camera(page);
  check(Math.abs(distance(after) - distance(before)) < 1e-3 * distance(before), `WebGL ${webgl}: orbit changed the distance to the target`);
  check(after.position.some((p, i) => Math.abs(p - before.position[i]) > 0.05), `WebGL ${webgl}: a mouse drag did not move the camera`);
  check(!(await canvasShot(page)).equals(shotBefore), `WebGL ${webgl}: the image did not change after an orbit`);

  // Dolly with the wheel: closer, same target.
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.wheel({ deltaY: -300 });
  await settle(page);
  const dollied = await camera(page);
  check(distance(dollied) < distance(after) * 0.9, `WebGL ${webgl}: the wheel did not dolly in (${distance(after)} -> ${distance(dollied)})`);

  // Pan with shift-drag: camera and target move together.
  await page.keyboard.down('Shift');
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 80, box.y + box.height / 2, { steps: 4 });
  await page.mouse.up();
  await page.keyboard.up('Shift');
  await settle(page);
  const panned = await camera(page);
  const moved = panned.target.map((t, i) => t - dollied.target[i]);
  const cameraMoved = panned.position.map((p, i) => p - dollied.position[i]);
  check(Math.hypot(...moved) > 0.05 && cameraMoved.every((m, i) => Math.abs(m - moved[i]) < 1e-3),
    `WebGL ${webgl}: shift-drag did not pan (target moved ${JSON.stringify(moved)}, camera ${JSON.stringify(cameraMoved)})`);

  // Technique switch: every object draws with the technique chosen.
  for (const t of webgl === 2 ? ['normal', 'pom', 'maxmip'] : ['normal', 'pom', 'relief']) {
    await page.select('#technique', t);
    await settle(page);
    const objects = await page.evaluate(() => window.parallax.report());
    // An object drawn otherwise must say why (a flat material: "pom -> normal: height_scale is 0 ...").
    const unexplained = objects.filter((o) => o.technique !== t && !o.notes.some((n) => n.startsWith(`${t} -> `)));
    check(objects.some((o) => o.technique === t) && unexplained.length === 0,
      `WebGL ${webgl}: technique switch to ${t} drew ${objects.map((o) => `${o.object}: ${o.technique} ${o.notes.join('; ')}`).join(', ')}`);
  }
  // The sample count: pom at 8 samples at most.
  await page.select('#technique', 'pom');
  await page.$eval('#samples', (e) => { e.value = '8'; e.dispatchEvent(new Event('change')); });
  await settle(page);
  const eight = await page.evaluate(() => window.parallax.report());
  check(eight.every((o) => /samples<=8\b/.test(o.variant) || !/samples<=/.test(o.variant)),
    `WebGL ${webgl}: 8 samples asked, variants ${eight.map((o) => o.variant).join(' | ')}`);
  await page.$eval('#samples', (e) => { e.value = '0'; e.dispatchEvent(new Event('change')); });
  await page.select('#technique', 'scene');
  await settle(page);

  // A real material opened as a folder (the gallery's tiles: JPEG albedo,
  // height in the normal map's alpha, DirectX green), through the file input.
  const folder = path.join(repo, 'tests/data/gallery/tiles');
  const input = await page.$('#scene-files');
  await input.uploadFile(...fs.readdirSync(folder).map((f) => path.join(folder, f)));
  const opened = await page.evaluate(() => window.parallax.opened());
  check(opened === true, `WebGL ${webgl}: opening tests/data/gallery/tiles failed: ${await errorText(page)}`);
  await settle(page);
  const tiles = await page.evaluate(() => window.parallax.report());
  check(tiles.length === 1 && tiles[0].material === 'tiles', `WebGL ${webgl}: the opened scene drew ${JSON.stringify(tiles.map((o) => o.material))}`);
  if (webgl === 2) {
    await (await page.$('#stage')).screenshot({ path: path.join(outDir, 'opened_tiles.png') });
  }

  // A broken scene dropped onto the page: refused, naming the file and the
  // JSON path; the tiles stay drawn.
  await page.evaluate(() => {
    const dt = new DataTransfer();
    const text = '{"materials": [{"name": "m", "technique": {"technique": "pom", "max_samples": "many"}}], "objects": []}';
    dt.items.add(new File([text], 'broken.json', { type: 'application/json' }));
    document.dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
  });
  const dropped = await page.evaluate(() => window.parallax.opened());
  const shown = await errorText(page);
  check(dropped === false && /broken\.json/.test(shown) && /materials\[0\]/.test(shown),
    `WebGL ${webgl}: a broken dropped scene showed "${shown}"`);
  const still = await page.evaluate(() => window.parallax.report());
  check(still.length === 1 && still[0].material === 'tiles', `WebGL ${webgl}: the broken scene replaced the last one`);
  r.broken_scene_message = shown;

  // A folder of several .json files (a JSON file that is not a scene at its
  // top, examples/assets/bricks.json, and a scene of ETC2 KTX files naming
  // "../assets/..."): the first is refused and the page asks for a choice;
  // choosing the ETC2 scene draws it from its camera.
  const read = (rel) => Array.from(fs.readFileSync(path.join(repo, rel)));
  const etc2 = fs.readdirSync(path.join(repo, 'examples/assets/bricks_etc2')).map((f) => `examples/assets/bricks_etc2/${f}`);
  const folderFiles = [{ path: 'examples/notes.json', bytes: Array.from(Buffer.from('{"notes": "not a scene"}')) },
    ...['examples/assets/bricks.json', 'examples/scenes/bricks_etc2.json', ...etc2].map((rel) => ({ path: rel, bytes: read(rel) }))];
  const first = await page.evaluate((files) => window.parallax.openFiles(files.map((f) => ({ path: f.path, bytes: new Uint8Array(f.bytes) }))), folderFiles);
  const hint = await errorText(page);
  check(first === false && /notes\.json/.test(hint) && /choose the scene/.test(hint),
    `WebGL ${webgl}: a folder whose first .json is not a scene showed "${hint}"`);
  const choice = await page.$$eval('#scene optgroup option', (o) => o.map((x) => x.value).filter((v) => v.endsWith('bricks_etc2.json')));
  check(choice.length === 1, `WebGL ${webgl}: the opened scenes are not listed under Scene`);
  if (choice.length === 1) {
    await page.select('#scene', choice[0]);
    await settle(page);
    const etcScene = await page.evaluate(() => window.parallax.report());
    const etcCamera = await camera(page);
    check((await errorText(page)) === '' && etcScene.length === 1 && etcScene[0].material === 'bricks' &&
      Math.abs(etcCamera.position[1] + 2.2) < 1e-4 && Math.abs(etcCamera.position[2] - 1.3) < 1e-4,
      `WebGL ${webgl}: choosing examples/scenes/bricks_etc2.json drew ${JSON.stringify(etcScene.map((o) => o.material))} ` +
      `from ${JSON.stringify(etcCamera.position)}: ${await errorText(page)}`);
  }
  // An ASTC file (astcenc's, tests/fixtures/third_party): the web build has no
  // CPU ASTC decoder for the reference and the planner, and says so.
  const astcScene = JSON.stringify({ materials: [{ name: 'm', albedo: 'astcenc_4x4.ktx', technique: 'normal' }],
    objects: [{ name: 'o', mesh: { type: 'plane', size: 2 }, material: 'm' }] });
  const astc = await page.evaluate((text, bytes) => window.parallax.openFiles([
    { path: 'astc/scene.json', bytes: new TextEncoder().encode(text) },
    { path: 'astc/astcenc_4x4.ktx', bytes: new Uint8Array(bytes) }]), astcScene, read('tests/fixtures/third_party/astcenc_4x4.ktx'));
  const astcMessage = await errorText(page);
  check(astc === false && /astcenc_4x4\.ktx/.test(astcMessage) && /not in this build/.test(astcMessage),
    `WebGL ${webgl}: an ASTC file in the web build showed "${astcMessage}"`);
  r.astc_message = astcMessage;

  // The hit-error overlay at 128 pixels against the exact reference.
  await page.select('#scene', 'bricks');
  await settle(page);
  await page.click('#overlay-button');
  await page.waitForFunction(() => !document.getElementById('overlay').hidden || !document.getElementById('error').hidden, { timeout: 300000 });
  const overlay = await page.$eval('#overlay-stats', (e) => e.textContent);
  check(/hit error mean [0-9.]+/.test(overlay), `WebGL ${webgl}: overlay: ${overlay} ${await errorText(page)}`);
  r.overlay = overlay.replace(/0 · 1 · 4\+ texels$/, '');
  if (webgl === 2) await (await page.$('#stage')).screenshot({ path: path.join(outDir, 'overlay_bricks.png') });

  check(messages.length === 0, `WebGL ${webgl}: the console said:\n    ${messages.join('\n    ')}`);
  await page.close();
}

// A phone: 390 x 844 CSS pixels at 3x, touch only. The panel goes under the
// view, and one finger orbits.
async function phone(r) {
  const { page, messages } = await openPage('webgl=2&scene=bricks', { width: 390, height: 844, deviceScaleFactor: 3, isMobile: true, hasTouch: true });
  const stage = await (await page.$('#stage')).boundingBox();
  const panel = await (await page.$('#panel')).boundingBox();
  check(panel.y >= stage.y + stage.height - 1 && stage.width <= 390, `phone: the panel is not under the view (${JSON.stringify({ stage, panel })})`);
  const overflow = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
  check(overflow <= 0, `phone: the page is ${overflow} CSS pixels wider than the screen`);
  const before = await camera(page);
  await page.touchscreen.touchStart(stage.x + 150, stage.y + 200);
  await page.touchscreen.touchMove(stage.x + 250, stage.y + 220);
  await page.touchscreen.touchEnd();
  await settle(page);
  const after = await camera(page);
  check(after.position.some((p, i) => Math.abs(p - before.position[i]) > 0.05), 'phone: a one-finger drag did not orbit');
  await page.screenshot({ path: path.join(outDir, 'phone.png') });
  check(messages.length === 0, `phone: the console said:\n    ${messages.join('\n    ')}`);
  r.phone = { stage, panel };
  await page.close();
}

// A browser without WebGL 2 (getContext('webgl2') gives null, as on older
// phones): the page asks for WebGL 2, draws on WebGL 1 and says so.
async function withoutWebgl2(r) {
  const page = await browser.newPage();
  const messages = [];
  page.on('console', (m) => messages.push(`${m.type()}: ${m.text()}`));
  page.on('pageerror', (e) => messages.push(`page error: ${e.message}`));
  await page.evaluateOnNewDocument(() => {
    const getContext = HTMLCanvasElement.prototype.getContext;
    HTMLCanvasElement.prototype.getContext = function (kind, ...rest) {
      return kind === 'webgl2' ? null : getContext.call(this, kind, ...rest);
    };
  });
  await page.setViewport({ width: 1100, height: 720 });
  await page.goto(`${base}?webgl=2&scene=bricks`, { waitUntil: 'load' });
  await page.evaluate(() => window.parallaxReady);
  await settle(page);
  const ctx = await page.evaluate(() => window.parallax.context());
  const line = await page.$eval('#context-line', (e) => e.textContent);
  check(ctx.webgl === 1 && ctx.es_major === 2 && /no WebGL 2 context: WebGL 1/.test(line),
    `without WebGL 2: the page made WebGL ${ctx.webgl} and said "${line}"`);
  check((await page.evaluate(() => window.parallax.report())).length > 0, 'without WebGL 2: nothing drawn');
  check(messages.length === 0, `without WebGL 2: the console said:\n    ${messages.join('\n    ')}`);
  r.fallback = line;
  await page.close();
}

// Every variant compiled and linked under ANGLE (the browser's translator).
async function compileAll(webgl, r) {
  const { page } = await openPage(`webgl=${webgl}&scene=default`);
  const list = await page.evaluate(() => window.parallax.compileAll());
  const bad = list.filter((v) => !v.ok);
  r.variants = { count: list.length, failed: bad.length, ms_total: list.reduce((s, v) => s + v.ms, 0), failures: bad.slice(0, 20),
    all: list.map((v) => ({ variant: v.variant, ok: v.ok, ms: Math.round(v.ms * 10) / 10 })) };
  check(list.length > 100, `WebGL ${webgl}: only ${list.length} variants enumerated`);
  for (const v of bad.slice(0, 5)) fail(`WebGL ${webgl}: ${v.variant}: ${v.error.split('\n').slice(0, 6).join(' / ')}`);
  await page.close();
}

// Each golden scene drawn in the page (offscreen, 128 x 128, one sample per
// pixel, as tests/gpu_golden_tests.cpp) against the native golden.
async function goldens(webgl, r) {
  const { page, messages } = await openPage(`webgl=${webgl}&scene=default`);
  const scenes = await page.evaluate(() => window.parallax.builtins());
  const es = webgl === 2 ? 3 : 2;
  r.goldens = {};
  for (const scene of scenes) {
    const png = await page.evaluate(async (s) => {
      window.parallax.loadBuiltin(s);
      return Array.from(window.parallax.renderPng(128, 128));
    }, scene);
    const file = path.join(outDir, `${scene}_webgl${webgl}.png`);
    fs.writeFileSync(file, Buffer.from(png));
    const golden = path.join(repo, `tests/golden/${scene}_es${es}.png`);
    const limit = { ...tolerances.default, ...(tolerances.scenes[scene] || {}), ...((tolerances.scenes[scene] || {})[`webgl${webgl}`] || {}) };
    let result;
    try {
      result = JSON.parse(execFileSync(parallax, ['compare', file, golden, '--format', 'json', '--threshold', String(limit.pixel_threshold),
        '--max-share', String(limit.max_differing_share), '--max-mean', String(limit.max_mean_difference),
        '--diff', path.join(outDir, `${scene}_webgl${webgl}_diff.png`)], { encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'] }));
    } catch (e) {
      if (e.status === 1 && e.stdout) result = JSON.parse(e.stdout);
      else { fail(`WebGL ${webgl}: ${scene}: parallax compare: ${e.stderr || e.message}`); continue; }
    }
    r.goldens[scene] = { max: result.max_difference, share: result.share, mean: result.mean, verdict: result.verdict, limit };
    check(result.verdict === 'pass', `WebGL ${webgl}: ${scene} against ${path.relative(repo, golden)}: share ${result.share.toFixed(4)} ` +
      `(limit ${limit.max_differing_share}), mean ${result.mean.toFixed(3)} (limit ${limit.max_mean_difference}), max ${result.max_difference}`);
  }
  // The check can fail: bricks drawn with normal mapping (no parallax) in
  // place of its planned technique must break bricks' limits.
  const wrong = await page.evaluate(() => {
    window.parallax.loadBuiltin('bricks');
    window.parallax.setTechnique('normal', 0);
    const png = Array.from(window.parallax.renderPng(128, 128));
    window.parallax.setTechnique('scene', 0);
    return png;
  });
  const wrongFile = path.join(outDir, `bricks_normal_mapped_webgl${webgl}.png`);
  fs.writeFileSync(wrongFile, Buffer.from(wrong));
  const bricksLimit = { ...tolerances.default, ...(tolerances.scenes.bricks || {}), ...(((tolerances.scenes.bricks || {})[`webgl${webgl}`]) || {}) };
  let verdict = 'pass';
  try {
    execFileSync(parallax, ['compare', wrongFile, path.join(repo, `tests/golden/bricks_es${es}.png`), '--threshold', String(bricksLimit.pixel_threshold),
      '--max-share', String(bricksLimit.max_differing_share), '--max-mean', String(bricksLimit.max_mean_difference)], { stdio: 'ignore' });
  } catch (e) { verdict = e.status === 1 ? 'fail' : `error ${e.status}`; }
  r.golden_sensitivity = verdict;
  check(verdict === 'fail', `WebGL ${webgl}: bricks drawn with normal mapping passed bricks' golden limits (${verdict}): the limits cannot tell parallax from none`);

  // The read-back is synchronous: the browser notes it once as a stall (a
  // performance message, not an error). Anything else fails.
  const other = messages.filter((m) => !/GPU stall due to ReadPixels/.test(m));
  check(other.length === 0, `WebGL ${webgl} goldens: the console said:\n    ${other.join('\n    ')}`);
  await page.close();
}

// Frame times per technique at 256 x 256 (medians of 15 after 3 warm-ups),
// as ratios to normal mapping: a report, as the native bench.
async function frameTimes(webgl, r) {
  const { page } = await openPage(`webgl=${webgl}&scene=bricks`);
  r.frame_times = await page.evaluate(() => {
    const p = window.parallax;
    const canvas = document.getElementById('canvas');
    canvas.style.width = '256px'; canvas.style.height = '256px';
    canvas.width = 256; canvas.height = 256;
    const out = {};
    const median = (times) => times.sort((a, b) => a - b)[(times.length - 1) / 2];
    for (const t of p.techniques()) {
      try { p.setTechnique(t.name, 0); } catch (e) { out[t.name] = { error: e.message }; continue; }
      // Timed to a pixel read back (waits for the frame), and to glFinish.
      const read = [], finish = [];
      for (let i = 0; i < 18; i++) { const ms = p.draw(256, 256, 2); if (i >= 3) read.push(ms); }
      for (let i = 0; i < 18; i++) { const ms = p.draw(256, 256, 1); if (i >= 3) finish.push(ms); }
      out[t.name] = { median_ms: median(read), finish_median_ms: median(finish), variant: p.report().map((o) => o.variant).join(' | ') };
    }
    return out;
  });
  const normal = r.frame_times.normal && r.frame_times.normal.median_ms;
  for (const v of Object.values(r.frame_times)) if (v.median_ms && normal) v.ratio = v.median_ms / normal;
  await page.close();
}

try {
  for (const webgl of versions) {
    console.log(`WebGL ${webgl}`);
    const r = (report.versions[`webgl${webgl}`] = {});
    await useThePage(webgl, r);
    if (webgl === 2) await phone(r);
    if (webgl === 2) await withoutWebgl2(r);
    await compileAll(webgl, r);
    console.log(`  ${r.variants.count} variants compiled and linked, ${r.variants.failed} failed (${(r.variants.ms_total / 1000).toFixed(1)} s)`);
    await goldens(webgl, r);
    for (const [s, g] of Object.entries(r.goldens)) console.log(`  golden ${s}: ${g.verdict} (max ${g.max}, share ${g.share.toFixed(4)}, mean ${g.mean.toFixed(3)})`);
    await frameTimes(webgl, r);
    console.log('  frame times: ' + Object.entries(r.frame_times).map(([t, v]) => `${t} ${v.median_ms ? v.median_ms.toFixed(2) + ' ms' : v.error}`).join(', '));
  }
} catch (e) {
  fail(`the run stopped: ${e.stack || e}`);
} finally {
  await browser.close();
  server.close();
}

// --- report -------------------------------------------------------------------
report.failures = failures;
fs.writeFileSync(path.join(outDir, 'report.json'), JSON.stringify(report, null, 2));
const md = [`# Web page test report\n\n${report.chromium}; \`bash tests/web/run.sh\`\n`];
for (const [v, r] of Object.entries(report.versions)) {
  md.push(`## ${v}: ${r.context ? r.context.version : '?'}\n`);
  if (r.variants) md.push(`Variants compiled and linked under ANGLE: ${r.variants.count - r.variants.failed} of ${r.variants.count}\n`);
  if (r.goldens) {
    md.push('| scene | max | share over 8 | mean | limit share / mean | verdict |\n| --- | --- | --- | --- | --- | --- |');
    for (const [s, g] of Object.entries(r.goldens))
      md.push(`| ${s} | ${g.max} | ${g.share.toFixed(4)} | ${g.mean.toFixed(3)} | ${g.limit.max_differing_share} / ${g.limit.max_mean_difference} | ${g.verdict} |`);
    md.push('');
  }
  if (r.frame_times) {
    md.push('| technique | median ms to read-back (256 x 256, bricks) | ratio to normal | median ms to glFinish |\n| --- | --- | --- | --- |');
    for (const [t, f] of Object.entries(r.frame_times)) md.push(`| ${t} | ${f.median_ms ? f.median_ms.toFixed(2) : f.error} | ${f.ratio ? f.ratio.toFixed(2) : ''} | ${f.finish_median_ms ? f.finish_median_ms.toFixed(2) : ''} |`);
    md.push('');
  }
  if (r.overlay) md.push(`Hit-error overlay (bricks): ${r.overlay}\n`);
}
fs.writeFileSync(path.join(outDir, 'report.md'), md.join('\n') + '\n');
// Every variant and what ANGLE said of it, per WebGL version (docs/web-shaders.md is one run's).
const table = [`# Every shader variant under ANGLE\n\nWritten by \`bash tests/web/run.sh --shader-table docs/web-shaders.md\` (${report.chromium}, ` +
  'headless, ANGLE over SwiftShader): each variant the library can build for the context (`enumerate_variants`), compiled and ' +
  'linked with its typed interface checked (`build_program`), with the time that took (the first includes the translator\'s start). ' +
  (Object.values(report.versions).every((r) => r.variants && r.variants.failed === 0)
    ? 'Every one compiled and linked as the library ships it: none needed a change for ANGLE.\n'
    : 'Variants marked **no** failed: `out/web/report.json` has their logs.\n')];
for (const [v, r] of Object.entries(report.versions)) {
  if (!r.variants) continue;
  table.push(`## ${v === 'webgl2' ? 'WebGL 2 (GLSL ES 3.00)' : 'WebGL 1 (GLSL ES 1.00)'}: ${r.variants.count - r.variants.failed} of ${r.variants.count} compiled and linked\n`);
  table.push('| variant | compiled and linked | ms |\n| --- | --- | --- |');
  for (const x of r.variants.all) table.push(`| \`${x.variant}\` | ${x.ok ? 'yes' : '**no**'} | ${x.ms} |`);
  table.push('');
}
fs.writeFileSync(path.join(outDir, 'shaders.md'), table.join('\n'));
if (args['shader-table']) fs.writeFileSync(args['shader-table'], table.join('\n'));
console.log(`report: ${path.relative(process.cwd(), path.join(outDir, 'report.md'))}`);
if (failures.length) {
  console.log(`\n${failures.length} failure(s):\n- ${failures.join('\n- ')}`);
  process.exit(1);
}
console.log('web test: passed');
