// mtcal serve in headless Chromium (Debian's, driven by playwright-core from web/): log in,
// upload the real ISO 230-2 file, confirm, see the machine on the fleet page, add an event, open
// the timeline, write compensation (the zip download), log out; every page at 1280x800 and at a phone's 390x844 without horizontal
// overflow and without JavaScript errors; screenshots into SHOTS.
// Usage: node serve_browser.mjs BASE_URL USER PASSWORD DATA_FILE SHOTS MACHINE_FILE
// Exit 77 (ctest SKIPPED) when Chromium or playwright-core is missing.
import { existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';

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
const [base, user, password, dataFile, shots, machineFile, recordId] = process.argv.slice(2);
mkdirSync(shots, { recursive: true });
let passed = 0, failed = 0;
const check = (cond, what) => { if (cond) passed++; else { failed++; console.log(`FAIL: ${what}`); } };

// The browser's profile goes when the run ends (it was left in the temporary folder).
const profile = mkdtempSync(join(tmpdir(), 'mtcal-chromium-'));
process.on('exit', () => rmSync(profile, { recursive: true, force: true }));
const context = await playwright.chromium.launchPersistentContext(profile, {
  executablePath: chromiumPath, headless: true, viewport: { width: 1280, height: 800 },
  args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
         '--no-first-run', '--disable-quic', '--disable-sync'],
});
const page = context.pages()[0] || await context.newPage();
// A loaded 2-core machine parses the 4.8 MB Plotly slowly: generous limits.
page.setDefaultTimeout(120000);
page.setDefaultNavigationTimeout(120000);
const errors = [];
page.on('pageerror', (e) => errors.push(String(e)));
// The server has no /favicon.ico: Chromium asks for it on every site and logs the 404 as a console
// error (it did not ask while requests were intercepted). Any other failed resource is an error.
page.on('console', (m) => {
  if (m.type() !== 'error') return;
  const url = m.location().url || '';
  if (m.text().startsWith('Failed to load resource') && url === `${base}/favicon.ico`) return;
  errors.push(m.text().startsWith('Failed to load resource') ? `${m.text()}: ${url}` : m.text());
});
page.on('dialog', (d) => { errors.push(`dialog: ${d.message()}`); d.dismiss(); });
// Nothing but this server: the pages work offline; a request anywhere else fails the test. (Not
// context.route: intercepting requests turns off Chromium's HTTP cache, and with it the cached
// /static/plotly.min.js and V8's code cache of it, so every page with plots compiled it again.)
const external = [];
context.on('request', (r) => { if (!r.url().startsWith(base) && !/^(data|blob):/.test(r.url())) external.push(r.url()); });

async function fits(name, sizes = [[1280, 800], [390, 844]]) {
  for (const [w, h] of sizes) {
    await page.setViewportSize({ width: w, height: h });
    await page.waitForTimeout(150);
    const over = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
    check(over <= 0, `${name} at ${w}x${h} overflows by ${over} px`);
    await page.screenshot({ path: join(shots, `${name}-${w}.png`), fullPage: false });
  }
  await page.setViewportSize({ width: 1280, height: 800 });
}

try {
  await page.goto(`${base}/fleet`);
  check(page.url().endsWith('/login'), `no session: /fleet should lead to /login, went to ${page.url()}`);
  await fits('login');
  await page.fill('#user', user);
  await page.fill('#password', password);
  await Promise.all([page.waitForNavigation(), page.click('#login')]);
  check(page.url().endsWith('/fleet'), `after login at ${page.url()}`);

  await page.goto(`${base}/upload`);
  await fits('upload');
  await page.setInputFiles('#upload-file', dataFile);
  await page.fill('#meta-machine', 'B02 <test stand>');
  await page.fill('#meta-date', '2022-10-20');
  await page.fill('#meta-operator', 'browser test');
  await Promise.all([page.waitForNavigation(), page.click('#upload-evaluate')]);
  const preview = await page.textContent('#preview');
  check(/A_up/.test(preview || '') && /E_down/.test(preview || ''), `the preview shows no ISO 230-2 figures: ${preview}`);
  await fits('upload-preview');
  await Promise.all([page.waitForNavigation(), page.click('#upload-confirm')]);
  check(page.url().includes('/machine?name='), `after confirming at ${page.url()}`);

  await page.goto(`${base}/fleet`);
  const fleet = await page.textContent('#fleet');
  check((fleet || '').includes('B02 <test stand>'), 'the uploaded machine is not on the fleet page');
  await fits('fleet');

  await page.click('text=B02 <test stand>');
  await page.waitForSelector('#plots .plot .main-svg');
  const plots = await page.$$eval('#plots .plot', (d) => d.length);
  check(plots >= 1, `the machine page drew ${plots} plots`);
  await page.fill('#event-date', '2022-11-01');
  await page.selectOption('#event-kind', 'compensation-loaded');
  await page.fill('#event-note', 'table <v2> loaded');
  await Promise.all([page.waitForNavigation(), page.click('#event-add')]);
  const events = await page.textContent('#events');
  check((events || '').includes('table <v2> loaded'), `the event is not listed: ${events}`);
  await fits('machine');
  // write compensation: the form's download is a zip (local file header "PK\x03\x04") named after
  // the machine and the controller, holding LinuxCNC's tables.
  await page.setInputFiles('#comp-machine', machineFile);
  await page.selectOption('#comp-format', 'linuxcnc');
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#comp-write')]);
  const zip = readFileSync(await download.path());
  check(zip.subarray(0, 4).toString('latin1') === 'PK\x03\x04', 'the compensation download is not a zip');
  check(/-linuxcnc\.zip$/.test(download.suggestedFilename()), `download named ${download.suggestedFilename()}`);
  check(zip.includes('.comp') || zip.includes('.ini') || zip.includes('.hal'), 'the zip names no LinuxCNC file');

  // write compensation from a recorded result (its machine file held in the store): a zip too.
  await page.goto(`${base}/record?id=${encodeURIComponent(recordId)}`);
  await page.selectOption('#rec-comp-format', 'linuxcnc');
  const [recDownload] = await Promise.all([page.waitForEvent('download'), page.click('#rec-comp-write')]);
  const recZip = readFileSync(await recDownload.path());
  check(recZip.subarray(0, 4).toString('latin1') === 'PK\x03\x04', 'the record\'s compensation download is not a zip');
  check(recDownload.suggestedFilename() === download.suggestedFilename(),
        `the record's download is named ${recDownload.suggestedFilename()}, the machine file's ${download.suggestedFilename()}`);
  await fits('record');

  // An admin sets the machine's calibration interval; the fleet shows it as the machine's own.
  await page.goto(`${base}/admin/machines`);
  await page.selectOption('#interval-machine', 'B02 <test stand>');
  await page.fill('#interval-days', '90');
  await Promise.all([page.waitForNavigation(), page.click('#interval-save')]);
  const intervals = await page.textContent('#intervals');
  check(/B02 <test stand>\s*90/.test(intervals || ''), `the interval is not listed: ${intervals}`);
  await fits('intervals');
  await page.goto(`${base}/fleet`);
  const cells = await page.$$eval('#fleet td', (tds) => tds.map((td) => td.textContent.trim()));
  check(cells.includes('90'), `the fleet does not show the interval of 90 days: ${cells.join(' | ')}`);
  await page.click('text=B02 <test stand>');
  await page.waitForSelector('#trend-link');

  await page.click('#trend-link');
  await page.waitForSelector('.js-plotly-plot .main-svg');
  // The trend report is the HTML report of `history trend --report`, laid out for 1280x800 (as
  // the reports' own browser test checks it), not for a phone.
  await fits('trend', [[1280, 800]]);

  await page.goto(`${base}/fleet`);
  await Promise.all([page.waitForNavigation(), page.click('#logout')]);
  check(page.url().endsWith('/login'), `after logout at ${page.url()}`);
  await page.goto(`${base}/fleet`);
  check(page.url().endsWith('/login'), 'after logout /fleet is still open');
} catch (e) {
  check(false, `browser run: ${e}`);
}
check(errors.length === 0, `JavaScript errors: ${errors.join(' | ')}`);
check(external.length === 0, `requests outside the server: ${external.join(' | ')}`);
await context.close();
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
