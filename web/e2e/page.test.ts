// The page in headless Chromium (e2e/harness.ts) on WebGPU's SwiftShader adapter: the default
// scene at 128x128 is the CLI's render (e2e/fixtures/render-128.json, made by `qjulia render
// --backend cpu` and held fresh by tests/architecture/web.rs) within CONTRACT_TOLERANCE; a share link
// reopens it; a preset renders; bad scenes show the CLI's error line; a drag orbits, a right
// drag pans and the wheel zooms; the scene saved after a drag, and a PNG exported, render to
// the page's picture with the CLI (the release binary beside web/, or QJULIA_BIN); the 2D view
// is render2d's; path mode accumulates to the CLI's picture; the zoom stops where f32 does; a
// scene naming the built-in map shows it with no prompt, and one naming a file asks for it,
// renders without it meanwhile, then as the CLI does once it is given.
// Without Chromium, WebGPU or the binary this fails, unless QJULIA_SKIP_BROWSER_TESTS=1 (then
// each test says it skipped).

import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { inflateSync } from 'node:zlib';
import type { Page } from 'playwright-core';
import { afterAll, beforeAll, describe, expect, test } from 'vitest';
import { SCHEMA } from '../src/scene';
import { type Harness, launch, open, root } from './harness';

const SKIP = process.env.QJULIA_SKIP_BROWSER_TESTS === '1';

let harness: Harness;
let page: Page;

beforeAll(async () => {
  if (SKIP) return;
  harness = await launch();
  page = await open(harness, '[image]\nwidth = 16\nheight = 16\n');
});

afterAll(async () => {
  await harness?.close();
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
  expect([r.width, r.height]).toEqual([128, 128]);
  assertAgrees(what, r, { rgb: Buffer.from(fixture.rgb, 'base64'), hit: Buffer.from(fixture.hit, 'base64') });
}

/// The page's picture (`r`) against a CLI render (its RGB bytes and hit mask) within
/// CONTRACT_TOLERANCE: masks on 99.5% of pixels, colour within 2/255 on 99%.
function assertAgrees(what: string, r: Rendered, cli: { rgb: Uint8Array; hit: Uint8Array }): void {
  const pixels = r.width * r.height;
  expect(cli.rgb.length).toBe(3 * pixels);
  let [masks, colours, hits, most] = [0, 0, 0, 0];
  for (let k = 0; k < pixels; k++) {
    const h = r.depth[k] !== null;
    hits += Number(h);
    masks += Number(h === (cli.hit[k] === 1));
    const c = r.colour[k];
    const worst = Math.max(...[0, 1, 2].map((ch) => Math.abs(((c >>> (8 * ch)) & 255) - cli.rgb[3 * k + ch])));
    most = Math.max(most, worst);
    colours += Number(worst <= 2);
  }
  console.log(
    `${what}: the page against the CLI: ${hits} hits of the CLI's ` +
      `${cli.hit.reduce((a, b) => a + b, 0)}, masks agree on ${masks} of ${pixels}, colour within ` +
      `2/255 on ${colours} (most ${most}/255)`,
  );
  expect(masks / pixels).toBeGreaterThanOrEqual(0.995);
  expect(colours / pixels).toBeGreaterThanOrEqual(0.99);
}

/// The qjulia binary the tests run (QJULIA_BIN, or the release build beside web/).
const QJULIA = process.env.QJULIA_BIN ?? join(root, '..', 'target', 'release', 'qjulia');

/// Runs the CLI in `dir`; throws with its stderr where it fails.
function cli(dir: string, args: string[]): string {
  if (!existsSync(QJULIA)) {
    throw new Error(`these tests run the CLI: build it (cargo build --release) or set QJULIA_BIN (no ${QJULIA})`);
  }
  return execFileSync(QJULIA, args, { cwd: dir, encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'] });
}

/// The CLI's refusal of a scene: its one error line without `error: `.
function cliRefusal(dir: string, args: string[]): string {
  try {
    cli(dir, args);
  } catch (e) {
    const stderr = String((e as { stderr?: string }).stderr ?? '');
    expect((e as { status?: number }).status).toBe(2);
    return stderr.trim().replace(/^error: /, '');
  }
  throw new Error(`the CLI took ${args.join(' ')}`);
}

/// An 8-bit, non-interlaced RGB or RGBA PNG's pixels as RGB (test code: the page's export and
/// the CLI's output compared).
function decodePng(bytes: Uint8Array): { width: number; height: number; rgb: Uint8Array } {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let at = 8;
  let [width, height, channels] = [0, 0, 0];
  const idat: Uint8Array[] = [];
  while (at < bytes.length) {
    const length = view.getUint32(at);
    const type = String.fromCharCode(...bytes.subarray(at + 4, at + 8));
    const data = bytes.subarray(at + 8, at + 8 + length);
    if (type === 'IHDR') {
      [width, height] = [view.getUint32(at + 8), view.getUint32(at + 12)];
      expect([data[8], data[12]]).toEqual([8, 0]);
      channels = { 2: 3, 6: 4 }[data[9]] ?? 0;
      expect(channels).toBeGreaterThan(0);
    }
    if (type === 'IDAT') idat.push(data);
    at += 12 + length;
  }
  const raw = inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const out = new Uint8Array(stride * height);
  for (let y = 0; y < height; y++) {
    const filter = raw[y * (stride + 1)];
    for (let x = 0; x < stride; x++) {
      const v = raw[y * (stride + 1) + 1 + x];
      const a = x >= channels ? out[y * stride + x - channels] : 0;
      const b = y > 0 ? out[(y - 1) * stride + x] : 0;
      const c = x >= channels && y > 0 ? out[(y - 1) * stride + x - channels] : 0;
      const p = a + b - c;
      const paeth =
        Math.abs(p - a) <= Math.abs(p - b) && Math.abs(p - a) <= Math.abs(p - c) ? a : Math.abs(p - b) <= Math.abs(p - c) ? b : c;
      const predicted = [0, a, b, (a + b) >> 1, paeth][filter];
      out[y * stride + x] = (v + predicted) & 255;
    }
  }
  const rgb = new Uint8Array(width * height * 3);
  for (let k = 0; k < width * height; k++) rgb.set(out.subarray(k * channels, k * channels + 3), 3 * k);
  return { width, height, rgb };
}

/// The CLI's render of a scene file in `dir`: RGB bytes and the hit mask (from --depth).
function cliRender(dir: string, scene: string, extra: string[] = []): { rgb: Uint8Array; hit: Uint8Array } {
  cli(dir, ['render', '--scene', scene, '-o', 'cli.png', '--depth', 'cli-depth.npy', ...extra]);
  const { rgb } = decodePng(new Uint8Array(readFileSync(join(dir, 'cli.png'))));
  const npy = readFileSync(join(dir, 'cli-depth.npy'));
  const header = npy.readUInt16LE(8);
  const depth = new Float32Array(npy.buffer.slice(npy.byteOffset + 10 + header, npy.byteOffset + npy.length));
  return { rgb, hit: Uint8Array.from(depth, (d) => (Number.isNaN(d) ? 0 : 1)) };
}

/// The CLI's render of a scene given as TOML text (saved as scene.toml in a new folder).
function cliRenderText(toml: string): { rgb: Uint8Array; hit: Uint8Array } {
  const dir = scratch();
  writeFileSync(join(dir, 'scene.toml'), toml);
  return cliRender(dir, 'scene.toml');
}

/// Calls `window.qjulia[name](...args)` in the page.
function q<T>(name: string, ...args: unknown[]): Promise<T> {
  return page.evaluate(
    ([n, a]) => {
      const api = (window as unknown as { qjulia: Record<string, (...x: unknown[]) => unknown> }).qjulia;
      return api[n as string](...(a as unknown[]));
    },
    [name, args] as const,
  ) as Promise<T>;
}

const scratch = () => mkdtempSync(join(tmpdir(), 'qjulia-e2e-'));
const base64 = (bytes: Uint8Array) => Buffer.from(bytes).toString('base64');

/// A left (or right) drag across the view, held across frames as a user's is.
async function drag(dx: number, dy: number, button: 'left' | 'right' = 'left'): Promise<void> {
  const box = (await page.locator('#view').boundingBox())!;
  const [x, y] = [box.x + box.width / 2, box.y + box.height / 2];
  await page.mouse.move(x, y);
  await page.mouse.down({ button });
  for (let k = 1; k <= 8; k++) {
    await page.mouse.move(x + (dx * k) / 8, y + (dy * k) / 8);
    await page.waitForTimeout(30);
  }
  await page.mouse.up({ button });
}

const DEFAULT_128 = '[image]\nwidth = 128\nheight = 128\n';

describe('the page', () => {
  test('renders the default scene as qjulia render does, within CONTRACT_TOLERANCE', async () => {
    if (skipped('default scene')) return;
    assertAgreesWithTheCli('rendered', await render(DEFAULT_128));
  });

  test('a share link reopens the same scene', async () => {
    if (skipped('share link')) return;
    const shared = await open(harness, DEFAULT_128);
    type Page2 = { qjulia: { text(): string; last(): Promise<Rendered | null> } };
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

  test('a mouse drag changes the view, and the scene saved renders the same with the CLI', async () => {
    if (skipped('drag and save')) return;
    const before = await render('[image]\nwidth = 96\nheight = 96\n');
    const eye = (toml: string) => /\[camera\]\neye = (\[[^\]]*\])/.exec(toml)![1];
    const eyeBefore = eye(await q<string>('scene'));
    await drag(120, 40);
    const after = (await q<Rendered>('last'))!;
    const saved = await q<string>('scene');
    expect(eye(saved)).not.toBe(eyeBefore);
    const changed = after.colour.filter((c, k) => c !== before.colour[k]).length;
    console.log(`a drag of 120 x 40 points: the eye from ${eyeBefore} to ${eye(saved)}, ${changed} pixels changed`);
    expect(changed).toBeGreaterThan(500);
    // Save: the page's TOML, rendered by the CLI (the GPU where there is one), is the page's
    // picture within CONTRACT_TOLERANCE.
    assertAgrees('saved after a drag', after, cliRenderText(saved));
  });

  test('a right drag pans and the wheel zooms', async () => {
    if (skipped('pan and zoom')) return;
    await render('[image]\nwidth = 48\nheight = 48\n');
    const target = (toml: string) => /\ntarget = (\[[^\]]*\])/.exec(toml)![1];
    await drag(30, 0, 'right');
    await q('last');
    expect(target(await q<string>('scene'))).not.toBe('[0.0, 0.0, 0.0]');
    const box = (await page.locator('#view').boundingBox())!;
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    await page.mouse.wheel(0, -200);
    await q('last');
    const eye = /\[camera\]\neye = \[([^\]]*)\]/.exec(await q<string>('scene'))![1].split(', ').map(Number);
    const t = target(await q<string>('scene')).slice(1, -1).split(', ').map(Number);
    const distance = Math.hypot(...eye.map((e, k) => e - t[k]));
    // One wheel turn of 200 points: the distance times exp(-0.4).
    expect(distance).toBeCloseTo(3 * Math.exp(-0.4), 9);
  });

  test('an exported PNG carries the scene: the CLI renders it again, and the page reopens it', async () => {
    if (skipped('PNG export')) return;
    const shown = await render('[image]\nwidth = 64\nheight = 48\n[fractal]\nc = [-0.1, 0.7, 0.1, 0.1]\n');
    const png = Buffer.from(await q<string>('png'), 'base64');
    const dir = scratch();
    writeFileSync(join(dir, 'page.png'), png);
    const exported = decodePng(png);
    expect([exported.width, exported.height]).toEqual([64, 48]);
    // The export is the picture shown, byte for byte.
    const rgb = Uint8Array.from({ length: 64 * 48 * 3 }, (_, k) => (shown.colour[Math.floor(k / 3)] >>> (8 * (k % 3))) & 255);
    expect(Buffer.from(exported.rgb).equals(Buffer.from(rgb))).toBe(true);
    assertAgrees('the exported PNG rendered by the CLI', shown, cliRender(dir, 'page.png'));
    const scene = await q<string>('scene');
    await render('');
    expect(await q('open', 'page.png', base64(png))).toBeNull();
    expect(await q<string>('scene')).toBe(scene);
  });

  test('a bad file gets the CLI\u2019s line, naming it', async () => {
    if (skipped('bad file')) return;
    const dir = scratch();
    const bad = '[camera]\nfov_y_degrees = 200.0\n';
    writeFileSync(join(dir, 'wide.toml'), bad);
    const line = cliRefusal(dir, ['render', '--scene', 'wide.toml', '-o', 'x.png']);
    expect(await q('open', 'wide.toml', base64(new TextEncoder().encode(bad)))).toBe(line);
    expect(await page.textContent('#error')).toBe(`error: ${line}`);
    expect(existsSync(join(dir, 'x.png'))).toBe(false);
  });

  test('the 2D view is the CLI\u2019s render2d', async () => {
    if (skipped('2D view')) return;
    const toml = '[image]\nwidth = 64\nheight = 64\n[view2d]\ncenter = [0.1, 0.2]\nextent = 3.0\n';
    await q('mode', true);
    const r = await render(toml);
    await q('mode', false);
    const dir = scratch();
    writeFileSync(join(dir, 'view.toml'), toml);
    cli(dir, ['render2d', '--scene', 'view.toml', '-o', 'cli2d.png']);
    const made = decodePng(new Uint8Array(readFileSync(join(dir, 'cli2d.png'))));
    let [same, most] = [0, 0];
    for (let k = 0; k < 64 * 64; k++) {
      const d = Math.abs((r.colour[k] & 255) - made.rgb[3 * k]);
      same += Number(d <= 2);
      most = Math.max(most, d);
    }
    console.log(`the 2D view: grey within 2/255 of render2d's on ${same} of ${64 * 64} (most ${most}/255)`);
    expect(same / (64 * 64)).toBeGreaterThanOrEqual(0.99);
  });

  test('path mode, accumulated, is the CLI\u2019s picture', async () => {
    if (skipped('path mode')) return;
    const toml =
      '[shading]\nmodel = "path"\n[path]\nbounces = 2\n[image]\nwidth = 40\nheight = 40\nsamples = 4\n' +
      'tone_map = "aces"\n';
    const r = await render(toml);
    assertAgrees('path mode, 4 samples', r, cliRenderText(toml));
  });

  test('path mode estimates its error, and renders to image.target_error in the CLI\u2019s passes', async () => {
    if (skipped('the error estimate')) return;
    const toml =
      '[shading]\nmodel = "path"\n[path]\nbounces = 2\n[image]\nwidth = 40\nheight = 40\nsamples = 256\n' +
      'target_error = 0.03\n';
    const r = (await render(toml)) as Rendered & {
      samples: number;
      estimate: { rmse: number; relative: number } | null;
      passes: { samples: number; estimated_relative_rmse: number | null }[];
    };
    const dir = scratch();
    writeFileSync(join(dir, 'scene.toml'), toml);
    const picture = cliRender(dir, 'scene.toml', ['--stats', 'stats.json']);
    const stats = JSON.parse(readFileSync(join(dir, 'stats.json'), 'utf8'));
    const theirs = stats.target_passes as { samples: number; estimated_relative_rmse: number }[];
    console.log(
      `image.target_error 0.03: the page's passes ${JSON.stringify(r.passes)}, the CLI's ${JSON.stringify(theirs)} ` +
        `(stopped by ${stats.stopped_by})`,
    );
    // The same passes: the first of 16 samples, each later one within 5% of the CLI's (the two
    // adapters' last bits move an estimate a little, and the schedule rounds it up), each
    // estimate within 10% of the CLI's, and the page shows its last pass with its estimate.
    expect(r.passes.length).toBe(theirs.length);
    expect(r.passes.length).toBeGreaterThanOrEqual(2);
    expect(r.passes[0].samples).toBe(16);
    r.passes.forEach((p, k) => {
      expect(Math.abs(p.samples / theirs[k].samples - 1)).toBeLessThanOrEqual(0.05);
      expect(Math.abs(p.estimated_relative_rmse! / theirs[k].estimated_relative_rmse - 1)).toBeLessThanOrEqual(0.1);
    });
    const last = r.passes.at(-1)!;
    expect(r.samples).toBe(last.samples);
    expect(r.estimate!.relative).toBe(last.estimated_relative_rmse);
    expect(last.estimated_relative_rmse! <= 0.03 || last.samples === 256).toBe(true);
    expect(Math.abs(r.estimate!.rmse / stats.estimated_rmse - 1)).toBeLessThanOrEqual(0.1);
    if (last.samples === theirs.at(-1)!.samples) assertAgrees('the last pass', r, picture);
    // The exported PNG records the estimate as `render` does (the text held to the library's
    // by test/estimate.test.ts).
    const exported = Buffer.from(await q<string>('png'), 'base64');
    const keyword = Buffer.from('qjulia-error\0');
    let [at, recorded] = [8, ''];
    while (at < exported.length) {
      const length = exported.readUInt32BE(at);
      const data = exported.subarray(at + 8, at + 8 + length);
      if (exported.toString('latin1', at + 4, at + 8) === 'tEXt' && data.subarray(0, keyword.length).equals(keyword)) {
        recorded = data.subarray(keyword.length).toString('latin1');
      }
      at += 12 + length;
    }
    expect(recorded).toBe(
      `estimated_rmse = ${r.estimate!.rmse}\nestimated_relative_rmse = ${r.estimate!.relative}\n` +
        `stopped_by = "${stats.stopped_by}"\nsamples = ${last.samples}\n`,
    );
    const error = (100 * r.estimate!.relative).toFixed(1);
    expect(await q<string>('status')).toContain(`samples ${last.samples}/${last.samples}, error ${error}%, pass ${r.passes.length} to 3.0%`);
  });

  test('a scene naming the built-in map shows it, asking for nothing, as the CLI does', async () => {
    if (skipped('the built-in map')) return;
    const toml =
      '[environment]\nfile = "qjulia:dusk.hdr"\nrotation_degrees = 40\n' +
      '[shading]\nenvironment_light = true\nambient = 0.5\n[image]\nwidth = 48\nheight = 48\n';
    const r = await render(toml);
    expect(await q('prompt')).toBeNull();
    expect(await q<string>('status')).not.toMatch(/environment map/);
    assertAgrees('the built-in map', r, cliRenderText(toml));
  });

  test('a scene naming a map file asks for it, renders without it meanwhile, then with it', async () => {
    if (skipped('a map file')) return;
    const toml = '[environment]\nfile = "sky.hdr"\n[image]\nwidth = 48\nheight = 48\n';
    const without = await render(toml);
    expect(await q<string>('prompt')).toMatch(/environment map\s+sky\.hdr/);
    expect(await q<string>('status')).toMatch(/environment map sky\.hdr not loaded/);
    assertAgrees('without the map', without, cliRenderText(toml.replace('sky.hdr', '')));
    const dusk = readFileSync(join(root, '..', 'assets', 'environment', 'dusk.hdr'));
    expect(await q('pickMap', dusk.toString('base64'))).toBeNull();
    const withMap = await q<Rendered>('last');
    expect(await q('prompt')).toBeNull();
    expect(await q<string>('scene')).toMatch(/checksum = 1760195408/);
    const dir = scratch();
    writeFileSync(join(dir, 'scene.toml'), toml);
    writeFileSync(join(dir, 'sky.hdr'), dusk);
    assertAgrees('with the map picked', withMap, cliRender(dir, 'scene.toml'));
  });

  test('zooming in stops where f32 stops resolving the view, and says why', async () => {
    if (skipped('zoom stop')) return;
    await render('[image]\nwidth = 32\nheight = 32\n');
    const box = (await page.locator('#view').boundingBox())!;
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    let turns = 0;
    while ((await q<string>('notice')) === '' && turns < 60) {
      await page.mouse.wheel(0, -1000);
      await page.waitForTimeout(20);
      turns++;
    }
    const notice = await q<string>('notice');
    console.log(`after ${turns} wheel turns: ${notice}`);
    expect(notice).toMatch(/WebGPU has no f64/);
    expect(notice).toMatch(/a pixel spans .* at the target, below the spacing of f32 values/);
    await q('last');
    // The view it stopped at still resolves: the CLI has no f32 warning for it.
    const dir = scratch();
    writeFileSync(join(dir, 'deep.toml'), await q<string>('scene'));
    const params = JSON.parse(cli(dir, ['gpu-params', '--scene', 'deep.toml', '--json']));
    expect(params.warnings).toEqual([]);
  });

  test('without WebGPU the page says so and links to the native build', async () => {
    if (skipped('no WebGPU')) return;
    const bare = await harness.browser.newPage();
    await bare.addInitScript(() => {
      delete (Navigator.prototype as unknown as { gpu?: unknown }).gpu;
    });
    await bare.goto(harness.origin);
    await bare.waitForFunction(() => /needs WebGPU/.test(document.querySelector('#status')?.textContent ?? ''));
    expect(await bare.textContent('#status')).toMatch(/^this browser has no WebGPU \(navigator.gpu\): the page needs WebGPU/);
    expect(await bare.getAttribute('#status a', 'href')).toMatch(/github/);
    await bare.close();
  });
});
