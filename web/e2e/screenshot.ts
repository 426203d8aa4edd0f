// The book's picture of the page (docs/browser.png) and its figures, taken in headless
// Chromium on SwiftShader (e2e/harness.ts): `npm run screenshot`. It opens the gallery preset
// at 256x256, takes the screenshot once the view is still, then measures the time to the first
// picture (page load to the first frame shown) and the frames of a drag at 256x256.

import { join } from 'node:path';
import { SCHEMA } from '../src/scene';
import { launch, open, root } from './harness';

const h = await launch();
try {
  const rabbit = SCHEMA.presets.find((p) => p.slug === 'rabbit')!;
  const toml = `${rabbit.toml.trim()}\n\n[image]\nwidth = 256\nheight = 256\nsamples = 4\n`;
  const started = Date.now();
  const page = await open(h, toml, { width: 1280, height: 860 });
  console.log(`first picture (load, pipeline, 4 samples) in ${Date.now() - started} ms`);
  await page.evaluate(() => (window as unknown as { qjulia: { last(): Promise<unknown> } }).qjulia.last());
  const out = join(root, '..', 'docs', 'browser.png');
  await page.screenshot({ path: out });
  console.log(`wrote ${out}`);
  // A drag: 40 moves, 25 ms apart, each a frame at half resolution; the frame times are the
  // status line's (first dispatch to readback) as the page reports them.
  const box = (await page.locator('#view').boundingBox())!;
  const [x, y] = [box.x + box.width / 2, box.y + box.height / 2];
  await page.mouse.move(x, y);
  await page.mouse.down();
  const times: number[] = [];
  const t0 = Date.now();
  for (let k = 1; k <= 40; k++) {
    await page.mouse.move(x + 4 * k, y + k);
    await page.waitForTimeout(25);
    const s = (await page.textContent('#status')) ?? '';
    const m = / (\d+) ms/.exec(s);
    if (m) times.push(Number(m[1]));
  }
  await page.mouse.up();
  const wall = Date.now() - t0;
  times.sort((a, b) => a - b);
  console.log(
    `a drag at 256x256 (frames at 128x128 while moving): median frame ${times[times.length >> 1]} ms ` +
      `(of ${times.length} readings; ${wall} ms for 40 moves)`,
  );
} finally {
  await h.close();
}
