// The book's picture of the page (docs/browser.png) and its figures, taken in headless
// Chromium on SwiftShader (e2e/harness.ts): `npm run screenshot`. It measures the time to the
// first picture (the page opened on the default scene at 256x256 until that is shown) and the
// frames of a drag there, then shows the path-traced preset at 256x256 and takes the screenshot
// once every sample is in.

import { join } from 'node:path';
import { SCHEMA } from '../src/scene';
import { launch, open, root } from './harness';

const h = await launch();
try {
  const started = Date.now();
  const page = await open(h, '[image]\nwidth = 256\nheight = 256\n', { width: 1280, height: 860 });
  console.log(`first picture (page load, pipeline, one sample of the default scene at 256x256) in ${Date.now() - started} ms`);
  // A drag: 40 moves, 25 ms apart; the frame times are the status line's (first dispatch to
  // readback) as the page reports them, at half resolution while it moves.
  const box = (await page.locator('#view').boundingBox())!;
  const [x, y] = [box.x + box.width / 2, box.y + box.height / 2];
  await page.mouse.move(x, y);
  await page.mouse.down();
  const times: number[] = [];
  const t0 = Date.now();
  for (let k = 1; k <= 40; k++) {
    await page.mouse.move(x + 4 * k, y + k);
    await page.waitForTimeout(25);
    const m = / (\d+) ms \(moving/.exec((await page.textContent('#status')) ?? '');
    if (m) times.push(Number(m[1]));
  }
  await page.mouse.up();
  const wall = Date.now() - t0;
  times.sort((a, b) => a - b);
  console.log(
    `a drag at 256x256 (128x128 frames while it moves): median frame ${times[times.length >> 1]} ms ` +
      `(${times.length} readings; 40 moves in ${wall} ms)`,
  );
  const preset = SCHEMA.presets.find((p) => p.slug === 'path-traced')!;
  const toml = preset.toml.replace('samples = 64', 'samples = 16\nwidth = 256\nheight = 256');
  const t1 = Date.now();
  const r = await page.evaluate(
    (t) => (window as unknown as { qjulia: { render(t: string): Promise<{ error?: string }> } }).qjulia.render(t),
    toml,
  );
  if (r.error !== undefined) throw new Error(r.error);
  console.log(`the path-traced preset at 256x256, 16 samples, in ${Date.now() - t1} ms`);
  const out = join(root, '..', 'docs', 'browser.png');
  await page.screenshot({ path: out });
  console.log(`wrote ${out}`);
} finally {
  await h.close();
}
