// RUN/report.html in Debian's Chromium (docs/report.md): it opens from disk with no console
// error and no request; its charts have one bar per (group, policy) and one dot per episode
// that results.json implies; the episode rows link a replay page only once it exists; the
// timeline is the chosen episode's.

import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';

import { chromium, docPicture, elapsed, hribench, makeRun, openPage, stem } from './support.mjs';

const start = Date.now();
const browser = await chromium();
const { dir, run, results } = makeRun('report');
try {
  const report = path.join(run, 'report.html');
  assert.ok(fs.existsSync(report), 'eval writes report.html');
  const { page, problems } = await openPage(browser, report);
  const count = (selector) => page.locator(selector).count();

  // Bars and dots, as many as results.json implies.
  const { aggregates, episodes } = results;
  assert.equal(await count('#csr-by-task rect.bar'), aggregates.task.filter((r) => r.csr !== null).length);
  assert.equal(await count('#csr-by-role rect.bar'), aggregates.role.filter((r) => r.csr !== null).length);
  const labelled = aggregates.overall.reduce((n, r) => n + Object.values(r.failures).filter((v) => v > 0).length, 0);
  assert.ok(labelled > 0, 'noop fails');
  assert.equal(await count('#failures rect.bar'), labelled);
  assert.equal(await count('#rsp circle.dot'), episodes.filter((e) => e.response_latency !== null).length);
  assert.equal(await count('#tsync circle.dot'), episodes.filter((e) => e.tsync !== null).length);
  // A bar's height is its CSR.
  for (const r of aggregates.task) {
    const group = r.task_id ? `${r.task_id} ${r.group}` : r.group;
    const bar = page.locator(`#csr-by-task rect.bar[data-policy="${r.policy}"][data-group="${group}"]`);
    assert.equal(Number(await bar.getAttribute('data-value')), r.csr.value);
  }
  assert.equal(await count('#headline tr'), 1 + aggregates.role.length + aggregates.overall.length);
  assert.equal(await count('#episodes tr.episode'), episodes.length);

  // No video and no replay yet: no links; the timeline is the first failed episode's.
  assert.equal(await count('#episodes a'), 0);
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
  console.log(`report page: ${(fs.statSync(report).size / 1e3).toFixed(0)} kB, test ${elapsed(start)}`);
} finally {
  await browser.close();
  fs.rmSync(dir, { recursive: true, force: true });
}
