// The 3D replay page in Debian's Chromium (docs/report.md): made from a saved log by
// `hribench replay-html`, it opens from disk with no console error and no request; seeking to
// a step's time puts the drawn end-effector where the log's X_WT says (read from the log by the
// Python module, not by the page); a screenshot shows the robot and the person (the pixels
// that change when either is hidden).

import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';

import { checkReplayAgainstLog, chromium, docPicture, elapsed, hribench, logSteps, makeRun, openPage, stem } from './support.mjs';

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
  // One frame per step, the end-effector at three steps (1 mm quantisation of the page), robot
  // and person pixels (what changes when each is hidden).
  await checkReplayAgainstLog(page, steps, name);
  const last = steps.time.length - 1;

  // Contact points: none at the start (the robot at home), some while the oracle holds the object.
  assert.ok(steps.contact_steps.length > 0, 'the oracle grasps');
  assert.equal((await page.evaluate((t) => { hribenchReplay.seek(t); return hribenchReplay.contactPoints(); }, steps.time[0])).length, 0);
  const held = steps.contact_steps[Math.floor(steps.contact_steps.length / 2)];
  const points = await page.evaluate((t) => { hribenchReplay.seek(t); return hribenchReplay.contactPoints(); }, steps.time[held]);
  assert.ok(points.length > 0, `contact points at step ${held}`);
  for (const p of points) assert.ok(Math.hypot(...p.map((v, i) => v - steps.tcp[held][i])) < 0.15, `a contact ${p} by the hand`);

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
