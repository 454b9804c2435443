// What the browser tests share (tests/web/*_test.mjs, docs/report.md): the tools they need
// (Node.js, Debian's Chromium, playwright-core from node_modules — a missing one fails the test
// with what to install, never passes it), a small real run made with the built `hribench`,
// a page opened from disk that records console errors and every request, a replay page checked
// against its log, the check of a whole run's pages (also tests/web/check_run_pages.mjs RUN),
// and a PNG decoder for screenshots.

import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import zlib from 'node:zlib';

export const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
export const binary = process.env.HRIBENCH_BINARY || path.join(root, 'build', 'hribench');
const chromiumPath = process.env.HRIBENCH_CHROMIUM || '/usr/bin/chromium';

function missing(what, install) {
  console.error(`FAIL: ${what} is missing: ${install}`);
  process.exit(1);
}

// playwright-core's chromium, after checking that everything the test needs is installed.
export async function chromium() {
  if (!fs.existsSync(chromiumPath)) {
    missing(`Chromium (${chromiumPath})`, 'install the Debian package chromium (scripts/install-deps.sh)');
  }
  if (!fs.existsSync(path.join(root, 'node_modules', 'playwright-core', 'package.json'))) {
    missing('node_modules/playwright-core', 'run scripts/install-deps.sh (npm ci installs package-lock.json)');
  }
  if (!fs.existsSync(binary)) missing(`the hribench command (${binary})`, 'build it (cmake --build build)');
  const { chromium: browserType } = await import(pathToFileURL(path.join(root, 'node_modules', 'playwright-core', 'index.mjs')));
  // WebGL without a GPU: Chromium's software renderer (SwiftShader through ANGLE).
  return browserType.launch({ executablePath: chromiumPath, args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader'] });
}

export function hribench(args) {
  const result = spawnSync(binary, args, { cwd: root, encoding: 'utf8' });
  if (result.status !== 0) {
    throw new Error(`hribench ${args.join(' ')} exited ${result.status}:\n${result.stdout}\n${result.stderr}`);
  }
  return result.stdout;
}

// A fresh run in a temporary folder: I1 point_pick with the oracle (succeeds) and noop (fails),
// one episode each, 15 s horizon, logs saved.
export function makeRun(name) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), `hribench_web_${name}_`));
  const run = path.join(dir, 'run');
  hribench(['eval', '--tasks', 'I1', '--policy', 'oracle,noop', '--episodes', '1', '--horizon', '15',
            '--threads', '2', '--save-logs', '--out', run]);
  return { dir, run, results: JSON.parse(fs.readFileSync(path.join(run, 'results.json'), 'utf8')) };
}

// The episode's log stem as eval::episode_stem writes it.
export function stem(episode) {
  return `${episode.task}__${episode.policy}__${episode.seed}__${episode.spec_hash.slice(0, 12)}`.replace(/[^A-Za-z0-9_.-]/g, '_');
}

// Opens `file` in a new page; `problems` collects console errors, page errors and any request
// that is not the file itself or in-memory (blob:, data:).
export async function openPage(browser, file, viewport = { width: 1100, height: 800 }) {
  const page = await browser.newPage({ viewport });
  const url = pathToFileURL(file).href;
  const problems = [];
  page.on('console', (m) => { if (m.type() === 'error') problems.push(`console error: ${m.text()}`); });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('request', (r) => {
    if (r.url() !== url && !r.url().startsWith('blob:') && !r.url().startsWith('data:')) problems.push(`request: ${r.url()}`);
  });
  await page.goto(url);
  return { page, problems };
}

// The log's step times, TCP positions and contact steps, through hribench.load_log
// (docs/python.md): the page's numbers are checked against the log read by other code.
export function logSteps(file) {
  const pythonPath = process.env.HRIBENCH_PYTHONPATH || path.join(root, 'build', 'python');
  const script = 'import hribench, json, sys; l = hribench.load_log(sys.argv[1]); ' +
                 'print(json.dumps({"time": l["time"].tolist(), "tcp": l["tcp_pose"][:, :3].tolist(), ' +
                 '"contact_steps": sorted(set(l["contacts"]["step"].tolist()))}))';
  const result = spawnSync('/usr/bin/python3', ['-c', script, file], {
    encoding: 'utf8', env: { ...process.env, PYTHONPATH: pythonPath } });
  if (result.status !== 0) {
    throw new Error(`FAIL: the Python module hribench (${pythonPath}) could not read the log; build it ` +
                    `(cmake --build build --target hribench_python):\n${result.stderr}`);
  }
  return JSON.parse(result.stdout);
}

// Pixels that differ by more than a little between two screenshots of the same size.
export function changedPixels(a, b) {
  assert.equal(a.pixels.length, b.pixels.length);
  let n = 0;
  for (let i = 0; i < a.pixels.length; i += 4) {
    const d = Math.abs(a.pixels[i] - b.pixels[i]) + Math.abs(a.pixels[i + 1] - b.pixels[i + 1]) +
              Math.abs(a.pixels[i + 2] - b.pixels[i + 2]);
    if (d > 30) ++n;
  }
  return n;
}

// On an open replay page of the log `steps` (logSteps): it has one frame per step; seeking to
// the first, middle and last step puts the drawn end-effector within 2 mm of the log's X_WT;
// hiding the robot, then the person, changes over 1 % of the view's pixels each. Returns the
// middle step's index.
export async function checkReplayAgainstLog(page, steps, what) {
  assert.equal(await page.evaluate(() => hribenchReplay.frames()), steps.time.length, what);
  const last = steps.time.length - 1;
  for (const k of [0, Math.floor(last / 2), last]) {
    const [time, position] = await page.evaluate((t) => [hribenchReplay.seek(t), hribenchReplay.endEffectorPosition()], steps.time[k]);
    assert.ok(Math.abs(time - steps.time[k]) < 1e-3, `${what}: seek(${steps.time[k]}) showed ${time}`);
    const error = Math.hypot(...position.map((v, i) => v - steps.tcp[k][i]));
    assert.ok(error < 2e-3, `${what}, step ${k}: the page's end-effector ${position} is ${error} m from the log's ${steps.tcp[k]}`);
  }
  await page.evaluate((t) => hribenchReplay.seek(t), steps.time[Math.floor(last / 2)]);
  const view = page.locator('#view');
  const shot = async () => decodePng(await view.screenshot({ type: 'png' }));
  const full = await shot();
  for (const category of ['robot', 'human']) {
    await page.evaluate((c) => hribenchReplay.setVisible(c, false), category);
    const without = await shot();
    await page.evaluate((c) => hribenchReplay.setVisible(c, true), category);
    const changed = changedPixels(full, without);
    assert.ok(changed > 0.01 * full.width * full.height, `${what}, ${category}: ${changed} pixels of ${full.width}x${full.height}`);
  }
  assert.equal(changedPixels(full, await shot()), 0, `${what}: shown again, the same picture`);
  return Math.floor(last / 2);
}

// Checks the pages of a run folder (RUN/report.html and every RUN/replay/*.html) in `browser`:
// each opens from disk with no console error and no request; the report has one bar per
// (group, policy) and per policy's failure label and one dot per episode with the metric, as
// results.json implies, and one row per episode; its links are exactly the run's videos and
// replay pages of its episodes (RUN/videos/STEM.mp4, RUN/replay/STEM.html), each an existing
// file; every replay page gets ready and matches its log (checkReplayAgainstLog). Returns
// what it counted.
export async function checkRunPages(browser, run) {
  const results = JSON.parse(fs.readFileSync(path.join(run, 'results.json'), 'utf8'));
  const { page, problems } = await openPage(browser, path.join(run, 'report.html'));
  const count = (selector) => page.locator(selector).count();
  const { aggregates, episodes } = results;
  assert.equal(await count('#csr-by-task rect.bar'), aggregates.task.filter((r) => r.csr !== null).length);
  assert.equal(await count('#csr-by-role rect.bar'), aggregates.role.filter((r) => r.csr !== null).length);
  const labelled = aggregates.overall.reduce((n, r) => n + Object.values(r.failures).filter((v) => v > 0).length, 0);
  assert.equal(await count('#failures rect.bar'), labelled);
  assert.equal(await count('#rsp circle.dot'), episodes.filter((e) => e.response_latency !== null).length);
  assert.equal(await count('#tsync circle.dot'), episodes.filter((e) => e.tsync !== null).length);
  assert.equal(await count('#headline tr'), 1 + aggregates.role.length + aggregates.overall.length);
  assert.equal(await count('#episodes tr.episode'), episodes.length);
  // The run's files of its episodes, and the report's links.
  const stems = new Set(episodes.map(stem));
  const files = (folder, extension) => (fs.existsSync(path.join(run, folder)) ? fs.readdirSync(path.join(run, folder)) : [])
    .filter((f) => f.endsWith(extension) && stems.has(f.slice(0, -extension.length))).map((f) => `${folder}/${f}`);
  const videos = files('videos', '.mp4');
  const replays = files('replay', '.html');
  const links = await page.locator('#episodes a').evaluateAll((as) => as.map((a) => a.getAttribute('href')));
  assert.deepEqual([...links].sort(), [...videos, ...replays].sort(), 'the report links every video and replay page, nothing else');
  assert.deepEqual(problems, [], 'report.html');
  await page.close();
  for (const replay of replays) {
    const opened = await openPage(browser, path.join(run, replay), { width: 640, height: 480 });
    await opened.page.waitForFunction(() => window.hribenchReplay && window.hribenchReplay.ready, null, { timeout: 60000 });
    const log = path.join(run, 'logs', `${path.basename(replay, '.html')}.hlog`);
    await checkReplayAgainstLog(opened.page, logSteps(log), replay);
    assert.deepEqual(opened.problems, [], replay);
    await opened.page.close();
  }
  return { episodes: episodes.length, videos: videos.length, replays: replays.length };
}

// RGBA pixels of an 8-bit RGB or RGBA, non-interlaced PNG (what Chromium's screenshots are).
export function decodePng(buffer) {
  assert.equal(buffer.subarray(1, 4).toString('latin1'), 'PNG');
  let at = 8;
  let width = 0, height = 0, channels = 0;
  const idat = [];
  while (at < buffer.length) {
    const length = buffer.readUInt32BE(at);
    const type = buffer.subarray(at + 4, at + 8).toString('latin1');
    const data = buffer.subarray(at + 8, at + 8 + length);
    if (type === 'IHDR') {
      width = data.readUInt32BE(0);
      height = data.readUInt32BE(4);
      assert.equal(data[8], 8, 'PNG bit depth');
      assert.equal(data[12], 0, 'PNG interlace');
      channels = { 2: 3, 6: 4 }[data[9]];
      assert.ok(channels, `PNG colour type ${data[9]}`);
    } else if (type === 'IDAT') {
      idat.push(data);
    }
    at += 12 + length;
  }
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const pixels = Buffer.alloc(width * height * 4);
  let previous = Buffer.alloc(stride);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const line = Buffer.from(raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1)));
    for (let i = 0; i < stride; ++i) {
      const a = i >= channels ? line[i - channels] : 0;
      const b = previous[i];
      const c = i >= channels ? previous[i - channels] : 0;
      let predictor = 0;
      if (filter === 1) predictor = a;
      else if (filter === 2) predictor = b;
      else if (filter === 3) predictor = (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c;
        const pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        predictor = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      line[i] = (line[i] + predictor) & 255;
    }
    for (let x = 0; x < width; ++x) {
      for (let k = 0; k < 4; ++k) pixels[(y * width + x) * 4 + k] = k < channels ? line[x * channels + k] : 255;
    }
    previous = line;
  }
  return { width, height, pixels };
}

// Writes a screenshot for docs/images when HRIBENCH_DOC_PICTURES names a folder
// (scripts/render-report-pictures.sh).
export function docPicture(name, png) {
  const dir = process.env.HRIBENCH_DOC_PICTURES;
  if (!dir) return;
  fs.mkdirSync(dir, { recursive: true });
  fs.writeFileSync(path.join(dir, name), png);
  console.log(`wrote ${path.join(dir, name)}`);
}

export function elapsed(start) {
  return `${((Date.now() - start) / 1000).toFixed(1)} s`;
}
