// RUN/report.html in Debian's Chromium (docs/report.md): it opens from disk with no console
// error and no request; its charts have one bar per (group, policy) and one dot per episode
// that results.json implies; the episode rows link a replay page only once it exists; the
// timeline is the chosen episode's.

import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';

import { checkRunPages, chromium, docPicture, elapsed, hribench, makeRun, openPage, stem } from './support.mjs';

const start = Date.now();
const browser = await chromium();
const { dir, run, results } = makeRun('report');
try {
  const report = path.join(run, 'report.html');
  assert.ok(fs.existsSync(report), 'eval writes report.html');
  // Bars, dots and rows, as many as results.json implies; no link yet.
  const { aggregates, episodes } = results;
  assert.deepEqual(await checkRunPages(browser, run), { episodes: 2, videos: 0, replays: 0 });
  const { page, problems } = await openPage(browser, report);
  const count = (selector) => page.locator(selector).count();
  assert.ok(await count('#failures rect.bar') > 0, 'noop fails');
  // A bar's height is its CSR.
  for (const r of aggregates.task) {
    const group = r.task_id ? `${r.task_id} ${r.group}` : r.group;
    const bar = page.locator(`#csr-by-task rect.bar[data-policy="${r.policy}"][data-group="${group}"]`);
    assert.equal(Number(await bar.getAttribute('data-value')), r.csr.value);
  }
  // The timeline is the first failed episode's.
  const failed = episodes.find((e) => !e.success);
  assert.ok(failed);
  const timelineText = await page.locator('#timeline-section + p').innerText();
  assert.match(timelineText, new RegExp(`^${stem(failed)} \\(the first failed episode with a saved log\\)`));
  assert.equal(await count('#timeline path.separation'), 1);
  assert.equal(await count('#timeline path.protective'), 1);
  assert.ok((await count('#timeline path.cue')) >= 1, 'the pointing cue is on the timeline');
  assert.deepEqual(problems, []);
  await page.close();

  // A replay page made, the report rewritten with the oracle's timeline: one link, to a file.
  const oracle = episodes.find((e) => e.policy === 'oracle');
  hribench(['replay-html', run, stem(oracle)]);
  assert.match(hribench(['report', run, '--format', 'html', '--episode', stem(oracle)]), /wrote .*report\.html/);
  const second = await openPage(browser, report);
  const links = second.page.locator('#episodes a');
  assert.equal(await links.count(), 1);
  const href = await links.first().getAttribute('href');
  assert.equal(href, `replay/${stem(oracle)}.html`);
  assert.ok(fs.existsSync(path.join(run, href)));
  assert.match(await second.page.locator('#timeline-section + p').innerText(), new RegExp(`^${stem(oracle)} \\(--episode\\)`));
  assert.deepEqual(second.problems, []);
  docPicture('report.png', await second.page.screenshot({ type: 'png' }));

  // What the README's main command does: the video and the replay of the first failure of each
  // task and policy (noop's here), the page rewritten; every link a file, every page clean.
  hribench(['video', run, '--failures', '1']);
  hribench(['replay-html', run, '--failures', '1']);
  hribench(['report', run, '--format', 'html']);
  assert.deepEqual(await checkRunPages(browser, run), { episodes: 2, videos: 1, replays: 2 });
  console.log(`report page: ${(fs.statSync(report).size / 1e3).toFixed(0)} kB, test ${elapsed(start)}`);
} finally {
  await browser.close();
  fs.rmSync(dir, { recursive: true, force: true });
}
