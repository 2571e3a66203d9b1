// A tiles page in its three states, in chromium-headless-shell with every request off this
// machine refused (scripts/tiles-pages.sh): opened from disk (the page says to serve it), served
// with its viewer's script on a CDN it cannot reach (the page says the script did not load, and
// --script-url), served with local viewer files (the panorama, no notice). Saves a screenshot of
// each and exits 1 unless each shows what it should.
//   node tiles_page_states.mjs FILE_URL CDN_URL LOCAL_URL OUT_PREFIX
import { chromium } from 'playwright-core';

const [fileUrl, cdnUrl, localUrl, out] = process.argv.slice(2);
const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium-headless-shell',
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--no-first-run',
         '--allow-file-access-from-files=false', '--disable-background-networking', '--disable-component-update'],
});
const context = await browser.newContext({ viewport: { width: 800, height: 450 }, deviceScaleFactor: 1 });
const offMachine = [];
await context.route('**/*', (route) => {
  const url = route.request().url();
  if (url.startsWith('file:') || url.startsWith('http://127.0.0.1')) return route.continue();
  offMachine.push(url);
  return route.abort('internetdisconnected');
});
const page = await context.newPage();
let failed = false;
for (const [name, url, expected] of [
  ['file', fileUrl, 'browsers do not load its tiles from file://'],
  ['offline', cdnUrl, "The viewer's script did not load from https://cdn.jsdelivr.net/"],
  ['local', localUrl, null],
]) {
  await page.goto(url + (url.includes('?') ? '&' : '?') + 'hfov=100&yaw=30&pitch=5');
  if (expected === null) {
    await page.waitForFunction(() => window.viewer && window.viewer.isLoaded(), null, { timeout: 60000 });
    await page.waitForTimeout(1500);
  } else {
    await page.waitForTimeout(1000);
  }
  const said = await page.evaluate(() => {
    const d = document.getElementById('why');
    return d && d.style.display !== 'none' ? d.textContent : null;
  });
  const ok = expected === null ? said === null : said !== null && said.includes(expected);
  console.log(`${name}: ${ok ? 'as expected' : 'NOT as expected'}; notice: ${said === null ? 'none' : JSON.stringify(said)}`);
  failed ||= !ok;
  await page.screenshot({ path: `${out}${name}.jpg`, type: 'jpeg', quality: 80 });
}
console.log(`requests off this machine refused: ${offMachine.length} (${[...new Set(offMachine.map((u) => new URL(u).host))].join(', ')})`);
await browser.close();
process.exit(failed ? 1 : 0);
