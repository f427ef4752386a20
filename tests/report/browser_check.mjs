// Loads mtcal HTML reports in headless Chromium (Debian's, driven by playwright-core): fails on
// any JavaScript error or dialog, checks that every plot rendered with data and fits the page at
// 1280x800, saves screenshots; prints each report to PDF (page.pdf, print CSS) and checks with
// poppler-utils that the PDF holds one non-blank image per plot (pdfimages) and that the pages
// rendered to pixels (pdftoppm) carry the plots' colours; no two labels (annotations) of a plot
// overlap.
// Usage: node browser_check.mjs SCREENSHOT_DIR REPORT.html:PLOTS [REPORT.html:PLOTS ...]
// Exit 77 (ctest SKIPPED) when Chromium or playwright-core is not installed, with the reason.
import { copyFileSync, existsSync, mkdirSync, readFileSync, readdirSync, rmSync } from 'node:fs';
import { spawnSync } from 'node:child_process';
import { basename, dirname, resolve } from 'node:path';
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
// Loading a report with its 4 MB of inlined Plotly took over 30 s on the shared 2-core machine
// with three browsers and the option sweep beside it (ctest -j2): the limits are for a hung page,
// not a measurement.
const LOAD_MS = 120000;
mkdirSync(outDir, { recursive: true });
// A fresh, empty profile (playwright passes it as --user-data-dir).
// --webgl-antialiasing-mode=none: WebGL without multisampling. Without a GPU, Chromium draws WebGL
// in software (SwiftShader), where every resize of a 3-D scene's canvas (Plotly sets its width and
// then its height, at plotGlPixelRatio 2, for the scene and again for its print image) reallocates
// and clears the multisampled buffers: 0.1-1 s each, 3.5 s of an eval-points load, 0.6 s without.
// No check here looks at edge smoothing: the plots, their fit, the print images and the PDF's
// non-blank images and colours are the same checks on the same page code.
// The browser's profile and each PDF's extracted images go when the run ends (15 MB a report with
// plots: they were left in the temporary folder).
const profile = mkdtempSync(join(tmpdir(), 'mtcal-chromium-'));
process.on('exit', () => rmSync(profile, { recursive: true, force: true }));
const context = await playwright.chromium.launchPersistentContext(profile, {
  executablePath: chromiumPath,
  headless: true,
  viewport: { width: 1280, height: 800 },
  args: ['--no-sandbox', '--disable-gpu', '--webgl-antialiasing-mode=none', '--disable-background-networking',
         '--disable-component-update', '--no-first-run', '--disable-quic', '--disable-sync'],
});
const poppler = spawnSync('pdfimages', ['-v']).error === undefined && spawnSync('pdftoppm', ['-v']).error === undefined;
if (!poppler) console.log('note: poppler-utils (pdfimages, pdftoppm) not installed: PDF pixels not checked');
// A binary PPM (P6) as {w, h, rgb}.
function readPpm(path) {
  const b = readFileSync(path);
  let pos = 0;
  const token = () => {
    while (b[pos] === 0x23 || b[pos] <= 0x20) { if (b[pos] === 0x23) while (b[pos] !== 0x0a) pos++; pos++; }
    const start = pos;
    while (b[pos] > 0x20) pos++;
    return b.toString('ascii', start, pos);
  };
  if (token() !== 'P6') return null;
  const w = Number(token()), h = Number(token()), max = Number(token());
  if (max !== 255) return null;
  return { w, h, rgb: b.subarray(pos + 1, pos + 1 + w * h * 3) };
}
// Share of pixels that differ from the most common colour (the background), and of strongly
// coloured pixels (plot traces; text is grey or black).
function pixelStats(img) {
  const counts = new Map();
  const n = img.w * img.h;
  for (let i = 0; i < n; i += 7) {
    const k = (img.rgb[3 * i] << 16) | (img.rgb[3 * i + 1] << 8) | img.rgb[3 * i + 2];
    counts.set(k, (counts.get(k) || 0) + 1);
  }
  let bg = 0, best = -1;
  for (const [k, c] of counts) if (c > best) { best = c; bg = k; }
  let other = 0, coloured = 0;
  for (let i = 0; i < n; i++) {
    const r = img.rgb[3 * i], g = img.rgb[3 * i + 1], b = img.rgb[3 * i + 2];
    if (((r << 16) | (g << 8) | b) !== bg) other++;
    if (Math.max(r, g, b) - Math.min(r, g, b) > 60) coloured++;
  }
  return { other: other / n, coloured: coloured / n };
}
// Every report is loaded through one URL per folder (a copy beside it, so relative references
// resolve alike): V8 then compiles the 3.5 MB of inlined Plotly once, from its cache, instead of
// once per report (measured 3.5 s -> 0.8 s per report load on the 2-core machine).
const aliases = new Set();
function alias(file) {
  const a = join(dirname(file), `.browser-check-${process.pid}.html`);
  copyFileSync(file, a);
  aliases.add(a);
  return a;
}
process.on('exit', () => { for (const a of aliases) rmSync(a, { force: true }); });
// One page (one renderer process, whose V8 holds that cache) for all reports; its handlers report
// to the report loaded now.
const page = await context.newPage();
let problems = [];
page.on('pageerror', (e) => problems.push(`JavaScript error: ${e.message}`));
page.on('console', (m) => { if (m.type() === 'error') problems.push(`console error: ${m.text()}`); });
page.on('dialog', async (d) => { problems.push(`dialog opened: ${d.message()}`); await d.dismiss(); });
// blob: URLs are objects of the page itself (Plotly.toImage draws the SVG through one).
page.on('request', (r) => { if (!/^(file|data|blob):/.test(r.url())) problems.push(`external request: ${r.url()}`); });
let passed = 0, failed = 0;
for (const spec of specs) {
  const i = spec.lastIndexOf(':');
  const file = resolve(spec.slice(0, i));
  const expected = Number(spec.slice(i + 1));
  problems = [];
  await page.goto('file://' + alias(file), { waitUntil: 'load', timeout: LOAD_MS });
  // Every plot div must hold a rendered Plotly graph with at least one trace with data.
  await page.waitForFunction((n) => document.querySelectorAll('.plot .main-svg').length >= n || n === 0, expected,
                             { timeout: LOAD_MS }).catch(() => problems.push(`plots did not render in ${LOAD_MS / 1000} s`));
  const plots = await page.evaluate(() => Array.from(document.querySelectorAll('.plot')).map((el) => ({
    id: el.id,
    traces: (el.data || []).length,
    points: (el.data || []).reduce((s, t) => s + ((t.x || t.values || t.r || []).length || 0), 0),
    svg: el.querySelectorAll('.main-svg').length,
  })));
  if (plots.length !== expected) problems.push(`expected ${expected} plots, found ${plots.length}`);
  for (const p of plots) if (p.traces === 0 || p.points === 0 || p.svg === 0) problems.push(`plot ${p.id} has no rendered data`);
  // Fits the page at 1280x800: nothing wider than the window, no plot drawn beyond its box.
  const fit = await page.evaluate(() => ({
    scroll: document.documentElement.scrollWidth,
    cropped: Array.from(document.querySelectorAll('.plot')).filter((el) => {
      const box = el.getBoundingClientRect();
      return Array.from(el.querySelectorAll('.main-svg, canvas')).some((c) => {
        const r = c.getBoundingClientRect();
        return r.width > 0 && (r.right > box.right + 1 || r.bottom > box.bottom + 1 || r.left < box.left - 1);
      });
    }).map((el) => el.id),
  }));
  if (fit.scroll > 1280) problems.push(`page is ${fit.scroll} px wide at a 1280 px window`);
  if (fit.cropped.length) problems.push(`plots drawn beyond their box: ${fit.cropped.join(', ')}`);
  // Static images for print: one per plot, made after rendering.
  await page.waitForFunction((n) => window.mtcalPending === 0 && document.querySelectorAll('img.plot-print').length >= n,
                             expected, { timeout: 60000 }).catch(() => problems.push('print images not made in 60 s'));
  // Labels (annotations: the ISO 230-2 brackets' A E M R B ...) never overlap one another.
  const overlaps = await page.evaluate(() => {
    const found = [];
    for (const el of document.querySelectorAll('.plot')) {
      const boxes = Array.from(el.querySelectorAll('g.annotation-text-g')).map((g) => ({
        text: g.textContent, r: g.getBoundingClientRect() }));
      for (let i = 0; i < boxes.length; i++)
        for (let j = i + 1; j < boxes.length; j++) {
          const a = boxes[i].r, b = boxes[j].r;
          if (a.width > 0 && b.width > 0 && a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom)
            found.push(`${el.id}: '${boxes[i].text}' and '${boxes[j].text}'`);
        }
    }
    return found;
  });
  if (overlaps.length) problems.push(`labels overlap: ${overlaps.join('; ')}`);
  const images = await page.evaluate(() => document.querySelectorAll('img.plot-print').length);
  if (images !== expected) problems.push(`expected ${expected} print images, found ${images}`);
  const tables = await page.evaluate(() => document.querySelectorAll('table').length);
  if (tables < 1) problems.push('no summary table');
  const shot = join(outDir, basename(file).replace(/\.html$/, '') + '.png');
  await page.screenshot({ path: shot, fullPage: true });
  // One 1280x800 screen with the first plot in view, as a reader sees it.
  await page.evaluate(() => { const p = document.querySelector('figure'); if (p) p.scrollIntoView({ block: 'center' }); });
  await page.screenshot({ path: shot.replace(/\.png$/, '-1280x800.png') });
  const pdf = join(outDir, basename(file).replace(/\.html$/, '') + '.pdf');
  await page.pdf({ path: pdf, format: 'A4', printBackground: true });
  if (poppler && expected > 0) {
    const dir = mkdtempSync(join(tmpdir(), 'mtcal-pdf-'));
    process.on('exit', () => rmSync(dir, { recursive: true, force: true }));
    // Embedded images (the plots; soft masks come out as .pgm and are skipped).
    spawnSync('pdfimages', [pdf, join(dir, 'img')]);
    const imgs = readdirSync(dir).filter((f) => f.endsWith('.ppm')).map((f) => pixelStats(readPpm(join(dir, f))));
    const nonBlank = imgs.filter((st) => st.other > 0.01 && st.coloured > 0.0005).length;
    if (nonBlank < expected) problems.push(`PDF: ${nonBlank} non-blank plot images of ${expected} (${imgs.length} images)`);
    // The pages as printed: the plots' colours are on them.
    spawnSync('pdftoppm', ['-r', '30', pdf, join(dir, 'page')]);
    const pages = readdirSync(dir).filter((f) => f.startsWith('page')).map((f) => pixelStats(readPpm(join(dir, f))));
    if (!pages.some((st) => st.coloured > 0.001)) problems.push(`PDF: no page with plot colours (${pages.length} pages)`);
  }
  if (problems.length) {
    failed++;
    console.log(`FAIL ${basename(file)}:\n  ${problems.join('\n  ')}`);
  } else {
    passed++;
    console.log(`ok   ${basename(file)}: ${plots.length} plots rendered, fit 1280x800, printed to ${pdf}, screenshot ${shot}`);
  }
}
await page.close();
// Where scripts do not run (an e-mail reader): the first report with plots, scripts off (CDP
// Emulation.setScriptExecutionDisabled): the <noscript> note shows and names the static copies,
// the empty plot boxes are hidden, the tables are there.
{
  const spec = specs.find((sp) => Number(sp.slice(sp.lastIndexOf(':') + 1)) > 0);
  if (spec) {
    const file = resolve(spec.slice(0, spec.lastIndexOf(':')));
    const page = await context.newPage();
    const cdp = await context.newCDPSession(page);
    await cdp.send('Emulation.setScriptExecutionDisabled', { value: true });
    await page.goto('file://' + alias(file), { waitUntil: 'load', timeout: LOAD_MS });
    const st = await page.evaluate(() => {
      const note = document.querySelector('div.noscript');
      return {
        note: note ? note.textContent : '',
        noteShown: note ? note.getBoundingClientRect().height > 0 : false,
        plotsShown: Array.from(document.querySelectorAll('.plot')).filter((el) => el.getBoundingClientRect().height > 0).length,
        tables: document.querySelectorAll('table').length,
        rendered: document.querySelectorAll('.main-svg').length,
      };
    });
    const problems = [];
    if (!st.noteShown || !st.note.includes('--report-pdf')) problems.push(`no visible <noscript> note naming --report-pdf (${st.note})`);
    if (st.plotsShown) problems.push(`${st.plotsShown} empty plot boxes shown`);
    if (st.rendered) problems.push('plots rendered although scripts are off');
    if (st.tables < 1) problems.push('no tables');
    await page.screenshot({ path: join(outDir, basename(file).replace(/\.html$/, '') + '-noscript-1280x800.png') });
    if (problems.length) {
      failed++;
      console.log(`FAIL ${basename(file)} without scripts:\n  ${problems.join('\n  ')}`);
    } else {
      passed++;
      console.log(`ok   ${basename(file)} without scripts: note shown, plot boxes hidden, ${st.tables} tables`);
    }
    await page.close();
  }
}
await context.close();
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
