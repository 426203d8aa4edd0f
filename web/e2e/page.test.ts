// The page in headless Chromium (Debian's /usr/bin/chromium, or QJULIA_CHROMIUM), driven by
// playwright-core, on WebGPU's SwiftShader adapter: the default scene at 128x128 is the CLI's
// render (e2e/fixtures/render-128.json, made by `qjulia render --backend cpu` and held fresh by
// tests/web.rs) within CONTRACT_TOLERANCE; a preset renders; a bad scene shows the CLI's error
// line. Without Chromium or WebGPU this fails, unless QJULIA_SKIP_BROWSER_TESTS=1 (then each
// test says it skipped).

import { existsSync, readFileSync } from 'node:fs';
import { createServer, type Server } from 'node:http';
import { extname, join } from 'node:path';
import { type Browser, type Page, chromium } from 'playwright-core';
import { build } from 'vite';
import { afterAll, beforeAll, describe, expect, test } from 'vitest';
import { SCHEMA } from '../src/scene';

const SKIP = process.env.QJULIA_SKIP_BROWSER_TESTS === '1';
const CHROMIUM = process.env.QJULIA_CHROMIUM ?? '/usr/bin/chromium';
/// WebGPU on SwiftShader, presenting without a display (the flags issue 21 measured).
const FLAGS = [
  '--no-sandbox',
  '--disable-gpu-sandbox',
  '--enable-unsafe-webgpu',
  '--enable-features=Vulkan',
  '--use-vulkan=swiftshader',
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--ignore-gpu-blocklist',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--no-first-run',
];
const root = join(import.meta.dirname, '..');
const dist = join(root, 'dist');

let server: Server;
let browser: Browser;
let page: Page;
let origin: string;

const TYPES: Record<string, string> = {
  '.html': 'text/html',
  '.js': 'text/javascript',
  '.css': 'text/css',
};

beforeAll(async () => {
  if (SKIP) return;
  if (!existsSync(CHROMIUM)) {
    throw new Error(
      `the browser tests need Chromium at ${CHROMIUM} (Debian: apt-get install chromium; or ` +
        'set QJULIA_CHROMIUM), or opt out with QJULIA_SKIP_BROWSER_TESTS=1',
    );
  }
  await build({ root, logLevel: 'warn' });
  server = createServer((req, res) => {
    const path = join(dist, decodeURIComponent((req.url ?? '/').split(/[?#]/)[0]));
    const file = path.endsWith('/') ? join(path, 'index.html') : path;
    if (!file.startsWith(dist) || !existsSync(file)) {
      res.writeHead(404).end();
      return;
    }
    res.writeHead(200, { 'content-type': TYPES[extname(file)] ?? 'application/octet-stream' });
    res.end(readFileSync(file));
  });
  await new Promise<void>((ok) => server.listen(0, '127.0.0.1', ok));
  const port = (server.address() as { port: number }).port;
  origin = `http://127.0.0.1:${port}`;
  browser = await chromium.launch({ executablePath: CHROMIUM, args: FLAGS, headless: true });
  page = await browser.newPage();
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  page.on('console', (m) => {
    if (m.type() === 'error' || m.type() === 'warning') console.log(`page ${m.type()}: ${m.text()}`);
  });
  await page.goto(`http://127.0.0.1:${port}/#${encodeURIComponent('[image]\nwidth = 16\nheight = 16\n')}`);
  await page.waitForFunction(
    () =>
      document.body.dataset.ready === 'true' ||
      /needs WebGPU/.test(document.querySelector('#status')?.textContent ?? ''),
    undefined,
    { timeout: 120_000 },
  );
  const ready = await page.evaluate(() => document.body.dataset.ready === 'true');
  if (!ready) {
    throw new Error(`the page found no WebGPU: ${await page.textContent('#status')}`);
  }
});

afterAll(async () => {
  await browser?.close();
  server?.close();
});

interface Rendered {
  error?: string;
  width: number;
  height: number;
  colour: number[];
  depth: (number | null)[];
  steps: number[];
}

const render = (toml: string): Promise<Rendered> =>
  page.evaluate((t) => (window as unknown as { qjulia: { render(t: string): Promise<Rendered> } }).qjulia.render(t), toml);

const skipped = (name: string) => {
  if (SKIP) console.log(`${name}: skipped because QJULIA_SKIP_BROWSER_TESTS=1`);
  return SKIP;
};

/// The page's picture against the CLI's (e2e/fixtures/render-128.json) within
/// CONTRACT_TOLERANCE: masks on 99.5% of pixels, colour within 2/255 on 99%.
function assertAgreesWithTheCli(what: string, r: Rendered): void {
  const fixture = JSON.parse(readFileSync(join(import.meta.dirname, 'fixtures/render-128.json'), 'utf8'));
  const rgb = Buffer.from(fixture.rgb, 'base64');
  const hit = Buffer.from(fixture.hit, 'base64');
  expect([r.width, r.height]).toEqual([128, 128]);
  const pixels = 128 * 128;
  let [masks, colours, hits, most] = [0, 0, 0, 0];
  for (let k = 0; k < pixels; k++) {
    const h = r.depth[k] !== null;
    hits += Number(h);
    masks += Number(h === (hit[k] === 1));
    const c = r.colour[k];
    const worst = Math.max(
      ...[0, 1, 2].map((ch) => Math.abs(((c >>> (8 * ch)) & 255) - rgb[3 * k + ch])),
    );
    most = Math.max(most, worst);
    colours += Number(worst <= 2);
  }
  console.log(
    `${what}: the page against qjulia render --backend cpu: ${hits} hits of the CLI's ` +
      `${hit.reduce((a, b) => a + b, 0)}, masks agree on ${masks} of ${pixels}, colour within ` +
      `2/255 on ${colours} (most ${most}/255)`,
  );
  expect(masks / pixels).toBeGreaterThanOrEqual(0.995);
  expect(colours / pixels).toBeGreaterThanOrEqual(0.99);
}

const DEFAULT_128 = '[image]\nwidth = 128\nheight = 128\n';

describe('the page', () => {
  test('renders the default scene as qjulia render does, within CONTRACT_TOLERANCE', async () => {
    if (skipped('default scene')) return;
    assertAgreesWithTheCli('rendered', await render(DEFAULT_128));
  });

  test('a share link reopens the same scene', async () => {
    if (skipped('share link')) return;
    const shared = await browser.newPage();
    await shared.goto(`${origin}/#${encodeURIComponent(DEFAULT_128)}`);
    await shared.waitForFunction(() => document.body.dataset.ready === 'true', undefined, {
      timeout: 120_000,
    });
    type Page2 = { qjulia: { text(): string; last(): Rendered | null } };
    expect(await shared.evaluate(() => (window as unknown as Page2).qjulia.text())).toBe(DEFAULT_128);
    const last = await shared.evaluate(() => (window as unknown as Page2).qjulia.last());
    assertAgreesWithTheCli('reopened from a share link', last!);
    await shared.close();
  });

  test('an invalid TOML shows the error line', async () => {
    if (skipped('invalid TOML')) return;
    const r = await render('[fractal\nepsilon = 1\n');
    // Where the parser stopped, as the CLI says it (`qjulia render --scene` adds toml-rs's
    // words: "unclosed table, expected `]`").
    expect(r.error).toBe('scene.toml: invalid TOML at line 1, column 9');
    expect(await page.textContent('#error')).toBe(`error: ${r.error}`);
  });

  test('a preset loads and renders', async () => {
    if (skipped('preset')) return;
    const rabbit = SCHEMA.presets.find((p) => p.slug === 'rabbit')!;
    const r = await render(`${rabbit.toml}\n[image]\nwidth = 48\nheight = 40\n`);
    expect(r.error).toBeUndefined();
    const hits = r.depth.filter((d) => d !== null).length;
    expect(hits).toBeGreaterThan(100);
    expect(hits).toBeLessThan(48 * 40);
  });

  test('a bad scene shows the CLI\u2019s error line', async () => {
    if (skipped('bad scene')) return;
    const r = await render('[fractal]\nepsilon = -1\n');
    expect(r.error).toBe('scene.toml: fractal.epsilon = -1: must be > 0');
    expect(await page.textContent('#error')).toBe('error: scene.toml: fractal.epsilon = -1: must be > 0');
  });
});
