// `node tests/web/check_run_pages.mjs RUN`: opens a run's report page and every replay page in
// Debian's Chromium and checks them (checkRunPages in support.mjs, docs/report.md): no console
// error, no request, the charts and rows results.json implies, links to exactly the run's videos
// and replay pages, every replay page against its own log. Prints what it counted; exits 1 on
// the first failure.

import path from 'node:path';

import { checkRunPages, chromium, elapsed } from './support.mjs';

if (process.argv.length !== 3) {
  console.error('usage: node tests/web/check_run_pages.mjs RUN');
  process.exit(2);
}
const start = Date.now();
const run = path.resolve(process.argv[2]);
const browser = await chromium();
try {
  const counted = await checkRunPages(browser, run);
  console.log(`${run}: report.html and ${counted.replays} replay pages pass (${counted.episodes} episodes, ` +
              `${counted.videos} videos linked), ${elapsed(start)}`);
} finally {
  await browser.close();
}
