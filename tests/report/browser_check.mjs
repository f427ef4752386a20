// Loads mtcal HTML reports in headless Chromium (Debian's, driven by playwright-core): fails on
// any JavaScript error or dialog, checks that every plot rendered with data, saves screenshots.
// Usage: node browser_check.mjs SCREENSHOT_DIR REPORT.html:PLOTS [REPORT.html:PLOTS ...]
// Exit 77 (ctest SKIPPED) when Chromium or playwright-core is not installed, with the reason.
import { existsSync, mkdirSync } from 'node:fs';
import { basename, resolve } from 'node:path';
import { createRequire } from 'node:module';
import { mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

const require = createRequire(import.meta.url);
const chromiumPath = process.env.MTCAL_CHROMIUM || '/usr/bin/chromium';
if (!existsSync(chromiumPath)) {
  console.log(`SKIPPED: no Chromium at ${chromiumPath} (scripts/install-deps installs Debian's chromium)`);
  process.exit(77);
}
let playwright;
try {
  playwright = require(resolve(process.env.MTCAL_WEB || '.', 'node_modules/playwright-core'));
} catch (e) {
  console.log(`SKIPPED: playwright-core is not installed (npm ci in web/): ${e.message}`);
  process.exit(77);
}

const [outDir, ...specs] = process.argv.slice(2);
mkdirSync(outDir, { recursive: true });
// A fresh, empty profile (playwright passes it as --user-data-dir).
const context = await playwright.chromium.launchPersistentContext(mkdtempSync(join(tmpdir(), 'mtcal-chromium-')), {
  executablePath: chromiumPath,
  headless: true,
  viewport: { width: 1200, height: 900 },
  args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
         '--no-first-run', '--disable-quic', '--disable-sync'],
});
let passed = 0, failed = 0;
for (const spec of specs) {
  const i = spec.lastIndexOf(':');
  const file = resolve(spec.slice(0, i));
  const expected = Number(spec.slice(i + 1));
  const page = await context.newPage();
  const problems = [];
  page.on('pageerror', (e) => problems.push(`JavaScript error: ${e.message}`));
  page.on('console', (m) => { if (m.type() === 'error') problems.push(`console error: ${m.text()}`); });
  page.on('dialog', async (d) => { problems.push(`dialog opened: ${d.message()}`); await d.dismiss(); });
  page.on('request', (r) => { if (!r.url().startsWith('file:') && !r.url().startsWith('data:')) problems.push(`external request: ${r.url()}`); });
  await page.goto('file://' + file, { waitUntil: 'load' });
  // Every plot div must hold a rendered Plotly graph with at least one trace with data.
  await page.waitForFunction((n) => document.querySelectorAll('.plot .main-svg').length >= n || n === 0, expected,
                             { timeout: 30000 }).catch(() => problems.push('plots did not render in 30 s'));
  const plots = await page.evaluate(() => Array.from(document.querySelectorAll('.plot')).map((el) => ({
    id: el.id,
    traces: (el.data || []).length,
    points: (el.data || []).reduce((s, t) => s + ((t.x || t.values || t.r || []).length || 0), 0),
    svg: el.querySelectorAll('.main-svg').length,
  })));
  if (plots.length !== expected) problems.push(`expected ${expected} plots, found ${plots.length}`);
  for (const p of plots) if (p.traces === 0 || p.points === 0 || p.svg === 0) problems.push(`plot ${p.id} has no rendered data`);
  const tables = await page.evaluate(() => document.querySelectorAll('table').length);
  if (tables < 1) problems.push('no summary table');
  const shot = join(outDir, basename(file).replace(/\.html$/, '') + '.png');
  await page.screenshot({ path: shot, fullPage: true });
  if (problems.length) {
    failed++;
    console.log(`FAIL ${basename(file)}:\n  ${problems.join('\n  ')}`);
  } else {
    passed++;
    console.log(`ok   ${basename(file)}: ${plots.length} plots rendered, screenshot ${shot}`);
  }
  await page.close();
}
await context.close();
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
