// Screenshots of panoproj's tile pyramids in the viewers themselves (scripts/tiles-oracle.sh):
// each page is opened in Debian's chromium-headless-shell (playwright-core, WebGL through
// SwiftShader) at a set view, controls hidden, and saved once every visible tile has loaded.
//   node tiles_viewers.mjs BASE_URL JOBS.json
// JOBS.json: [{"page": "pannellum/index.html", "yaw": 0, "pitch": 0, "hfov": 90, "out": "shot.png"}, ...]
import { readFileSync } from 'node:fs';
import { chromium } from 'playwright-core';

const [base, jobsFile] = process.argv.slice(2);
const jobs = JSON.parse(readFileSync(jobsFile, 'utf8'));
const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium-headless-shell',
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-quic', '--no-first-run',
         '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
const page = await browser.newPage({ viewport: { width: 800, height: 600 }, deviceScaleFactor: 1 });
page.on('pageerror', (e) => console.log('page error:', e.message));
for (const job of jobs) {
  const url = `${base}/${job.page}?yaw=${job.yaw}&pitch=${job.pitch}&hfov=${job.hfov}&controls=0`;
  await page.goto(url);
  if (job.page.startsWith('pannellum')) {
    // Loaded, and no tile request pending for 1 s.
    await page.waitForFunction(() => window.viewer && window.viewer.isLoaded(), null, { timeout: 60000 });
    let quiet = 0;
    while (quiet < 10) {
      const loading = await page.evaluate(() => window.viewer.getRenderer().isLoading());
      quiet = loading ? 0 : quiet + 1;
      await page.waitForTimeout(100);
    }
  } else {
    // Marzipano's stage says when a render had every visible tile ("stable").
    await page.evaluate(() => new Promise((done) => {
      const stage = window.viewer.stage();
      const check = (stable) => { if (stable) { stage.removeEventListener('renderComplete', check); done(); } };
      stage.addEventListener('renderComplete', check);
      stage.emit('renderInvalid');
    }));
    await page.waitForTimeout(500);
  }
  await page.screenshot({ path: job.out });
  console.log(`${job.page} yaw ${job.yaw} pitch ${job.pitch} hfov ${job.hfov}: ${job.out}`);
}
await browser.close();
