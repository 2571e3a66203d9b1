// Drives tests/browser/threejs_presets.html in Debian's Chromium (playwright-core): prints each
// view's PSNR between three.js's equirect background and the preset's cube map, and exits 1
// unless every view agrees (>= 25 dB: both are resampled, the equirect by three.js itself) and
// the wrong convention is far off (>= 10 dB less).
import { chromium } from 'playwright-core';

const url = process.argv[2];
const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-quic', '--no-first-run',
         '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
const page = await browser.newPage();
page.on('console', (m) => console.log('page:', m.text()));
page.on('pageerror', (e) => console.log('page error:', e.message));
await page.goto(url);
await page.waitForFunction(() => window.ready === true, null, { timeout: 60000 });
const rows = await page.evaluate(() => window.compare());
await browser.close();
let ok = true;
for (const r of rows) {
  const pass = r.preset >= 25 && r.preset - r.wrong >= 10;
  ok = ok && pass;
  console.log(`view ${JSON.stringify(r.dir).padEnd(16)} preset=threejs ${r.preset.toFixed(2)} dB, preset=unity ${r.wrong.toFixed(2)} dB ${pass ? '' : 'FAIL'}`);
}
process.exit(ok ? 0 : 1);
