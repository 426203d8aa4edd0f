// The page: a scene as the same TOML `qjulia render --scene` reads (from the URL fragment, or
// the default), checked by the loader's twin with the CLI's messages, traced by the same WGSL
// on WebGPU and shown in a canvas. `window.qjulia` is what the end-to-end tests drive.

import { type Rendered, Tracer } from './gpu';
import { SceneError, SceneLoader, type Scene } from './scene';

const status = document.querySelector<HTMLParagraphElement>('#status')!;
const error = document.querySelector<HTMLParagraphElement>('#error')!;
const text = document.querySelector<HTMLTextAreaElement>('#scene')!;
const canvas = document.querySelector<HTMLCanvasElement>('#view')!;
const NATIVE = 'https://github.com/qjulia/qjulia#two-commands';

/// A scene from TOML text over the defaults, as `qjulia render --scene FILE` loads it.
export function loadScene(toml: string, name = 'scene.toml'): Scene {
  const loader = new SceneLoader();
  loader.tomlStr(toml, { kind: 'file', path: name });
  return loader.build();
}

/// Shows a render in the canvas: the tracer's 0xFFBBGGRR pixels are RGBA bytes as they are.
function show(r: Rendered): void {
  canvas.width = r.width;
  canvas.height = r.height;
  const bytes = new Uint8ClampedArray(r.colour.byteLength);
  bytes.set(new Uint8Array(r.colour.buffer, r.colour.byteOffset, r.colour.byteLength));
  const image = new ImageData(bytes, r.width, r.height);
  canvas.getContext('2d')!.putImageData(image, 0, 0);
}

async function start(): Promise<void> {
  const tracer = await Tracer.create();
  if (typeof tracer === 'string') {
    status.innerHTML = `${tracer}: the page needs WebGPU. Use the <a href="${NATIVE}">native build</a>.`;
    return;
  }
  status.textContent = `WebGPU: ${tracer.adapterName}`;
  const render = async (toml: string): Promise<Rendered | string> => {
    try {
      const r = await tracer.render(loadScene(toml));
      show(r);
      error.textContent = '';
      status.textContent = `WebGPU: ${tracer.adapterName}; ${r.width}x${r.height} in ${r.milliseconds.toFixed(0)} ms`;
      return r;
    } catch (e) {
      if (!(e instanceof SceneError)) throw e;
      error.textContent = `error: ${e.message}`;
      return e.message;
    }
  };
  const fragment = decodeURIComponent(location.hash.slice(1));
  text.value = fragment;
  let last: Rendered | null = null;
  const renderText = async (toml: string) => {
    const r = await render(toml);
    if (typeof r !== 'string') last = r;
    return r;
  };
  document.querySelector('#render')!.addEventListener('click', () => void renderText(text.value));
  // A share link: this page with the scene's TOML in the fragment, which the page opens.
  document.querySelector('#share')!.addEventListener('click', () => {
    location.hash = encodeURIComponent(text.value);
    void navigator.clipboard?.writeText(location.href).catch(() => undefined);
  });
  const plain = (r: Rendered) => ({
    width: r.width,
    height: r.height,
    colour: [...r.colour],
    depth: [...r.depth].map((d) => (Number.isNaN(d) ? null : d)),
    steps: [...r.steps],
  });
  (window as unknown as { qjulia: unknown }).qjulia = {
    adapter: tracer.adapterName,
    /// Renders TOML; the pixels (colour, depth, steps as plain arrays) or the error line.
    async render(toml: string) {
      const r = await renderText(toml);
      return typeof r === 'string' ? { error: r } : plain(r);
    },
    /// The last picture shown (the share link's, once the page has opened it).
    last: () => (last === null ? null : plain(last)),
    /// The scene text the page holds.
    text: () => text.value,
  };
  await renderText(fragment);
  document.body.dataset.ready = 'true';
}

void start();
