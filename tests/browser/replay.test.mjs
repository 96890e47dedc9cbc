// The HTML replay in a real browser: Debian's headless Chromium (software WebGL), driven by
// playwright-core. Opens the page the e2e test `replay.rs` wrote, then checks that
//   - it loads with no console errors and no page errors,
//   - the WebGL canvas is not blank,
//   - two frames of the swinging pendulum differ, and where they differ is where the
//     pendulum's arm is (its projected box in either frame),
//   - the scrubber and the play button work.
// Usage: node replay.test.mjs [PAGE] (default: ../../target/tmp/replay/pendulum.html)

import { chromium } from 'playwright-core';
import { check } from './check.mjs';
import { existsSync } from 'node:fs';
import { fileURLToPath, pathToFileURL } from 'node:url';
import path from 'node:path';

const here = path.dirname(fileURLToPath(import.meta.url));
const page_path = path.resolve(process.argv[2] ?? path.join(here, '../../target/tmp/replay/pendulum.html'));
if (!existsSync(page_path)) {
  console.error(`no replay page at ${page_path}: run the e2e tests first (cargo test -p gymfleet-e2e)`);
  process.exit(1);
}
const executablePath = process.env.CHROMIUM ?? '/usr/bin/chromium';

const browser = await chromium.launch({
  executablePath,
  headless: true,
  args: [
    '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    '--disable-quic', '--no-first-run', '--disable-background-networking',
    '--disable-component-update', '--disable-sync',
  ],
});
try {
  const page = await browser.newPage({ viewport: { width: 800, height: 600 } });
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('requestfailed', (r) => errors.push(`request failed: ${r.url().slice(0, 80)}`));
  await page.goto(pathToFileURL(page_path).href);
  await page.waitForFunction(() => window.replay?.ready === true, null, { timeout: 30000 });

  // The canvas's pixels (RGBA) at frame `i`, and the arm's box on screen.
  const shot = (i) => page.evaluate((i) => {
    window.replay.setFrame(i);
    const src = window.replay.canvas;
    const c = document.createElement('canvas');
    c.width = src.width; c.height = src.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(src, 0, 0);
    const px = ctx.getImageData(0, 0, c.width, c.height).data;
    return { w: c.width, h: c.height, px: Array.from(px), arm: window.replay.screenBox(1) };
  }, i);

  const frames = await page.evaluate(() => window.replay.frames);
  check(frames > 100, `the page has the recording's frames (${frames})`);
  const first = await shot(0);
  const colours = new Set();
  for (let k = 0; k < first.px.length; k += 4 * 7) colours.add(first.px.slice(k, k + 3).join(','));
  check(first.w > 300 && first.h > 300, `the canvas fills the view (${first.w}x${first.h})`);
  check(colours.size > 20, `the canvas is not blank (${colours.size} colours sampled)`);

  const last = await shot(frames - 1);
  const margin = 4;
  const inside = (x, y, b) => x >= b.left - margin && x <= b.right + margin && y >= b.top - margin && y <= b.bottom + margin;
  let changed = 0, outside = 0;
  for (let y = 0; y < first.h; y++) {
    for (let x = 0; x < first.w; x++) {
      const k = 4 * (y * first.w + x);
      const d = Math.abs(first.px[k] - last.px[k]) + Math.abs(first.px[k + 1] - last.px[k + 1]) + Math.abs(first.px[k + 2] - last.px[k + 2]);
      if (d > 24) {
        changed++;
        if (!inside(x, y, first.arm) && !inside(x, y, last.arm)) outside++;
      }
    }
  }
  check(changed > 200, `two frames of the swing differ (${changed} pixels)`);
  check(outside <= changed * 0.02, `they differ where the arm is (${outside} of ${changed} changed pixels elsewhere)`);
  const moved = Math.abs((first.arm.left + first.arm.right) - (last.arm.left + last.arm.right)) / 2;
  check(moved > 5, `the arm moved on screen (${moved.toFixed(1)} px)`);

  // The controls: the scrubber sets the frame, play advances it.
  await page.evaluate(() => window.replay.setFrame(0));
  await page.fill('#scrub', '50');
  await page.dispatchEvent('#scrub', 'input');
  check((await page.textContent('#label')).startsWith('frame 51 /'), 'the scrubber moves to a frame');
  await page.click('#play');
  await page.waitForFunction(() => !document.getElementById('label').textContent.startsWith('frame 51 /'), null, { timeout: 10000 });
  check(true, 'play advances the frames');
  check(errors.length === 0, `no console or page errors${errors.length ? ': ' + errors.join(' | ') : ''}`);
} finally {
  await browser.close();
}
