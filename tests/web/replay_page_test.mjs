// The 3D replay page in Debian's Chromium (docs/report.md): made from a saved log by
// `hribench replay-html`, it opens from disk with no console error and no request; seeking to
// a step's time puts the drawn end-effector where the log's X_WT says (read from the log by the
// Python module, not by the page); a screenshot shows the robot and the person (the pixels
// that change when either is hidden).

import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';

import { chromium, decodePng, docPicture, elapsed, hribench, makeRun, openPage, root, stem } from './support.mjs';

// The log's step times and TCP positions, through hribench.load_log (docs/python.md).
function logSteps(file) {
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
function changedPixels(a, b) {
  assert.equal(a.pixels.length, b.pixels.length);
  let n = 0;
  for (let i = 0; i < a.pixels.length; i += 4) {
    const d = Math.abs(a.pixels[i] - b.pixels[i]) + Math.abs(a.pixels[i + 1] - b.pixels[i + 1]) +
              Math.abs(a.pixels[i + 2] - b.pixels[i + 2]);
    if (d > 30) ++n;
  }
  return n;
}

const start = Date.now();
const browser = await chromium();
const { dir, run, results } = makeRun('replay');
try {
  const oracle = results.episodes.find((e) => e.policy === 'oracle');
  const name = stem(oracle);
  assert.match(hribench(['replay-html', run, name]), /wrote .*replay/);
  const file = path.join(run, 'replay', `${name}.html`);
  const steps = logSteps(path.join(run, 'logs', `${name}.hlog`));

  const { page, problems } = await openPage(browser, file, { width: 960, height: 720 });
  await page.waitForFunction(() => window.hribenchReplay && window.hribenchReplay.ready, null, { timeout: 60000 });
  assert.equal(await page.evaluate(() => hribenchReplay.frames()), steps.time.length);

  // The end-effector as drawn at three steps, against the log (1 mm quantisation of the page).
  const last = steps.time.length - 1;
  for (const k of [0, Math.floor(last / 2), last]) {
    const [time, position] = await page.evaluate((t) => [hribenchReplay.seek(t), hribenchReplay.endEffectorPosition()], steps.time[k]);
    assert.ok(Math.abs(time - steps.time[k]) < 1e-3, `seek(${steps.time[k]}) showed ${time}`);
    const error = Math.hypot(...position.map((v, i) => v - steps.tcp[k][i]));
    assert.ok(error < 2e-3, `step ${k}: the page's end-effector ${position} is ${error} m from the log's ${steps.tcp[k]}`);
  }

  // Contact points: none at the start (the robot at home), some while the oracle holds the object.
  assert.ok(steps.contact_steps.length > 0, 'the oracle grasps');
  assert.equal((await page.evaluate((t) => { hribenchReplay.seek(t); return hribenchReplay.contactPoints(); }, steps.time[0])).length, 0);
  const held = steps.contact_steps[Math.floor(steps.contact_steps.length / 2)];
  const points = await page.evaluate((t) => { hribenchReplay.seek(t); return hribenchReplay.contactPoints(); }, steps.time[held]);
  assert.ok(points.length > 0, `contact points at step ${held}`);
  for (const p of points) assert.ok(Math.hypot(...p.map((v, i) => v - steps.tcp[held][i])) < 0.15, `a contact ${p} by the hand`);

  // Robot and person pixels: what changes when each is hidden.
  await page.evaluate((t) => hribenchReplay.seek(t), steps.time[Math.floor(last / 2)]);
  const view = page.locator('#view');
  const shot = async () => decodePng(await view.screenshot({ type: 'png' }));
  const full = await shot();
  for (const category of ['robot', 'human']) {
    await page.evaluate((c) => hribenchReplay.setVisible(c, false), category);
    const without = await shot();
    await page.evaluate((c) => hribenchReplay.setVisible(c, true), category);
    const changed = changedPixels(full, without);
    assert.ok(changed > 0.01 * full.width * full.height, `${category}: ${changed} pixels of ${full.width}x${full.height}`);
  }
  assert.equal(changedPixels(full, await shot()), 0, 'shown again, the same picture');

  // The controls: play moves time on, pause stops it; the scrubber and an event marker seek.
  await page.evaluate(() => hribenchReplay.seek(0));
  await page.click('#play');
  await page.waitForFunction(() => hribenchReplay.time() > 0.2, null, { timeout: 20000 });
  await page.click('#play');
  const paused = await page.evaluate(() => hribenchReplay.time());
  await page.waitForTimeout(300);
  assert.equal(await page.evaluate(() => hribenchReplay.time()), paused);
  await page.locator('#scrub').fill(String(last));
  assert.ok(Math.abs(await page.evaluate(() => hribenchReplay.time()) - steps.time[last]) < 1e-3);
  const marker = page.locator('.marker.cue').first();
  const cueTime = Number((await marker.getAttribute('title')).split(' s:')[0]);
  await marker.click();
  assert.ok(Math.abs(await page.evaluate(() => hribenchReplay.time()) - cueTime) <= 0.025 + 1e-9);
  assert.deepEqual(problems, []);
  // The documentation's frame: the oracle holding the object, its contact points shown.
  await page.evaluate((t) => hribenchReplay.seek(t), steps.time[held]);
  docPicture('replay.png', await page.screenshot({ type: 'png' }));
  console.log(`replay page: ${(fs.statSync(file).size / 1e6).toFixed(2)} MB for ${steps.time.length} steps, test ${elapsed(start)}`);
} finally {
  await browser.close();
  fs.rmSync(dir, { recursive: true, force: true });
}
