// The documentation site in chromium-headless-shell with every request off this machine
// refused (scripts/docs-pages.sh): the front page, the Python API page, the projections page
// at its formulas and the C++ reference at convert.hpp. Saves a screenshot of each and exits 1 if a page asked for anything off the
// machine, a request failed, or the formulas did not render (MathJax's SVG output counted).
//   node docs_pages.mjs BASE_URL OUT_PREFIX
import { chromium } from 'playwright-core';

const [base, out] = process.argv.slice(2);
const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium-headless-shell',
  args: ['--no-sandbox', '--no-first-run', '--disable-background-networking', '--disable-component-update'],
});
const context = await browser.newContext({ viewport: { width: 1280, height: 900 }, deviceScaleFactor: 1 });
const offMachine = [], failedRequests = [];
await context.route('**/*', (route) => {
  const url = route.request().url();
  if (url.startsWith('http://127.0.0.1')) return route.continue();
  offMachine.push(url);
  return route.abort('internetdisconnected');
});
const page = await context.newPage();
page.on('requestfailed', (r) => failedRequests.push(r.url()));
page.on('response', (r) => { if (r.status() >= 400) failedRequests.push(`${r.url()} (${r.status()})`); });
let failed = false;
for (const [name, path, anchor, formulas] of [
  ['front', 'index.html', null, 0],
  ['python', 'python.html', 'api-reference', 0],
  ['projection', 'projections.html', 'the-main-forms-in-formulas', 20],
  ['cpp', 'cpp.html', 'header-panoproj-convert-hpp', 0],
]) {
  await page.goto(`${base}/${path}${anchor ? '#' + anchor : ''}`);
  await page.waitForLoadState('networkidle');
  await page.waitForTimeout(1500);
  const rendered = await page.evaluate(() => document.querySelectorAll('mjx-container svg').length);
  const title = await page.title();
  await page.screenshot({ path: `${out}${name}.png` });
  console.log(`${name}: "${title}", ${rendered} formulas rendered`);
  if (rendered < formulas) {
    console.log(`${name}: expected at least ${formulas} rendered formulas`);
    failed = true;
  }
}
for (const u of offMachine) console.log(`asked for ${u} (off the machine)`);
for (const u of failedRequests) console.log(`failed: ${u}`);
await browser.close();
process.exit(failed || offMachine.length || failedRequests.length ? 1 : 0);
