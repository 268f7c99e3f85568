// Measures (does not assert) the app's time to first paint: loads the page in headless
// Chromium a few times, each in a fresh context with an empty cache, and prints the
// `paretomesh-first-paint` mark (set when the 3-D view first draws, see src/web/ui.rs) in ms
// after navigation start. Usage: node tests/e2e/first-paint.mjs [loads]
import { withApp, waitForApp } from './harness.mjs';

const loads = Number(process.argv[2] ?? 5);
await withApp(async ({ browser, url }) => {
  const times = [];
  for (let i = 0; i < loads; i++) {
    const context = await browser.newContext({ viewport: { width: 1400, height: 850 } });
    const page = await context.newPage();
    await page.goto(url);
    await waitForApp(page);
    times.push(await page.evaluate(() => performance.getEntriesByName('paretomesh-first-paint')[0].startTime));
    await context.close();
  }
  times.sort((a, b) => a - b);
  console.log(`first paint over ${loads} cold loads: min ${times[0].toFixed(0)} ms, median ${times[Math.floor(loads / 2)].toFixed(0)} ms, max ${times[loads - 1].toFixed(0)} ms`);
});
