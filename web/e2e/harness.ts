// The page in headless Chromium (Debian's /usr/bin/chromium, or QJULIA_CHROMIUM), driven by
// playwright-core, on WebGPU's SwiftShader adapter: the page built (vite) and served from
// dist/ on 127.0.0.1, and a browser with the flags a webgpu canvas and compute need without a
// display (issue 21 measured them). The end-to-end tests and the screenshot script use it.

import { existsSync, readFileSync } from 'node:fs';
import { createServer, type Server } from 'node:http';
import { extname, join } from 'node:path';
import { type Browser, type Page, chromium } from 'playwright-core';
import { build } from 'vite';

export const CHROMIUM = process.env.QJULIA_CHROMIUM ?? '/usr/bin/chromium';
/// WebGPU on SwiftShader, presenting without a display.
export const FLAGS = [
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
export const root = join(import.meta.dirname, '..');
const dist = join(root, 'dist');

const TYPES: Record<string, string> = {
  '.html': 'text/html',
  '.js': 'text/javascript',
  '.css': 'text/css',
};

export interface Harness {
  server: Server;
  browser: Browser;
  origin: string;
  close(): Promise<void>;
}

/// Builds the page, serves dist/ and starts Chromium; throws, saying what to do, without it.
export async function launch(): Promise<Harness> {
  if (!existsSync(CHROMIUM)) {
    throw new Error(
      `the browser tests need Chromium at ${CHROMIUM} (Debian: apt-get install chromium; or ` +
        'set QJULIA_CHROMIUM), or opt out with QJULIA_SKIP_BROWSER_TESTS=1',
    );
  }
  await build({ root, logLevel: 'warn' });
  const server = createServer((req, res) => {
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
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: FLAGS, headless: true });
  return {
    server,
    browser,
    origin: `http://127.0.0.1:${port}`,
    async close() {
      await browser.close();
      server.close();
    },
  };
}

/// Opens the page with `toml` in the fragment and waits until it shows it (or says it has no
/// WebGPU, which throws).
export async function open(h: Harness, toml: string, viewport = { width: 1200, height: 800 }): Promise<Page> {
  const page = await h.browser.newPage({ viewport });
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  page.on('console', (m) => {
    if (m.type() === 'error' || m.type() === 'warning') console.log(`page ${m.type()}: ${m.text()}`);
  });
  await page.goto(`${h.origin}/#${encodeURIComponent(toml)}`);
  await page.waitForFunction(
    () =>
      document.body.dataset.ready === 'true' ||
      /needs WebGPU/.test(document.querySelector('#status')?.textContent ?? ''),
    undefined,
    { timeout: 120_000 },
  );
  if (!(await page.evaluate(() => document.body.dataset.ready === 'true'))) {
    throw new Error(`the page found no WebGPU: ${await page.textContent('#status')}`);
  }
  return page;
}
