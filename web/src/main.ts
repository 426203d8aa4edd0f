// The page: the explorer in the browser. A scene is the same TOML `qjulia render --scene` reads
// (from the URL fragment, a file, a preset or the text box), checked by the loader's twin with
// the CLI's messages, traced by the same WGSL on WebGPU and shown in a canvas at the scene's
// image size. The panel edits any key; the mouse, touch and wheel move the camera as the
// desktop explorer does (src/camera.ts); while the view moves it renders at half resolution
// with one sample, then at full resolution, adding a dispatch of samples a frame up to
// image.samples, so that the still view is the picture `qjulia render` makes of the scene.
// A scene's environment map (`environment.file`): a built-in one is fetched with the page
// (Vite copies assets/environment/ into the build); any other the page asks for with a file
// picker. Until the map is there the view renders without it, and the status line says so.
// `window.qjulia` is what the end-to-end tests drive.

import duskUrl from '../../assets/environment/dusk.hdr?url';
import * as camera from './camera';
import { BUILTIN_PREFIX, type EnvironmentMap, type MapFormat, builtinChecksum, loadMap, mapFormat, mapNotice } from './envmap';
import { ERROR_PNG_KEYWORD, FIRST_PASS, errorText, nextSamples } from './estimate';
import { type Job, type Rendered, Tracer } from './gpu';
import { type HeatMap, COLOUR_STOPS, divergenceView, samplesView, stepsView } from './heatmap';
import { Panel } from './panel';
import { sceneOf, withScene, withText } from './png';
import { julia2dWarnings, sliceWarnings } from './precision';
import {
  type MapChecksums,
  SCHEMA,
  type Scene,
  SceneError,
  SceneLoader,
  type Source,
  sceneToToml,
  setAlgebra,
} from './scene';

const NATIVE = 'https://github.com/qjulia/qjulia#two-commands';
/// How long after the last move the view counts as still (milliseconds).
const SETTLE_MS = 180;
/// The moving view's resolution relative to the scene's.
const MOVING_SCALE = 0.5;
/// Where the page fetches the built-in maps' bytes (BUILTIN_MAPS of src/envmap.rs).
const BUILTIN_URLS: Record<string, string> = { 'dusk.hdr': duskUrl };
/// Maps kept loaded (LOADED_KEPT of src/envmap.rs).
const MAPS_KEPT = 2;

const $ = <T extends HTMLElement>(id: string) => document.getElementById(id) as T;
const status = $<HTMLParagraphElement>('status');
const notice = $<HTMLParagraphElement>('notice');
const error = $<HTMLParagraphElement>('error');
const text = $<HTMLTextAreaElement>('scene');
const canvas = $<HTMLCanvasElement>('view');
const modeMenu = $<HTMLSelectElement>('mode');
const presetMenu = $<HTMLSelectElement>('preset');
const envPrompt = $<HTMLParagraphElement>('envmap');
const envName = $<HTMLElement>('envmap-name');
const envFile = $<HTMLInputElement>('envmap-file');

/// A scene from TOML text over the defaults, as `qjulia render --scene FILE` loads it;
/// `checksums` as SceneLoader.build takes them.
export function loadScene(toml: string, name = 'scene.toml', checksums?: MapChecksums): Scene {
  const loader = new SceneLoader();
  loader.tomlStr(toml, { kind: 'file', path: name });
  return loader.build(checksums);
}

/// The scene the moving view renders: half the resolution, one sample.
function movingScene(s: Scene): Scene {
  const m = new Map(s);
  for (const k of ['image.width', 'image.height']) {
    m.set(k, Math.max(1, Math.round((s.get(k) as number) * MOVING_SCALE)));
  }
  m.set('image.samples', 1);
  return m;
}

/// Whether a render of `s` adds passes until its estimated error is at most
/// `image.target_error` (Scene::targets_error: path mode, a target > 0, `image.samples` > 1).
function targetsError(s: Scene): boolean {
  return (
    s.get('shading.model') === 'path' && (s.get('image.target_error') as number) > 0 && (s.get('image.samples') as number) > 1
  );
}

/// `s` with `samples` samples a pixel: one pass of a render to `image.target_error`.
function passScene(s: Scene, samples: number): Scene {
  const m = new Map(s);
  m.set('image.samples', samples);
  return m;
}

/// A pass of a render to `image.target_error`: its samples and its estimated relative error
/// (`--stats`' `target_passes`).
export interface TargetPass {
  samples: number;
  estimated_relative_rmse: number | null;
}

/// Samples each pixel took: minus the accumulator's state once a pixel is done, else all the
/// samples taken so far.
function samplesOf(r: Rendered): number[] {
  const a = r.accumulated;
  return Array.from({ length: r.width * r.height }, (_, k) =>
    a !== null && a[4 * k + 3] < 0 ? -a[4 * k + 3] : r.taken,
  );
}

class Explorer {
  scene: Scene;
  twoD = false;
  private home: Scene;
  private job: Job | null = null;
  private jobKey = '';
  private lastMove = -Infinity;
  private pending = false;
  private wake: (() => void) | null = null;
  private idleWaiters: (() => void)[] = [];
  /// The last picture shown at full resolution, and whether it has every sample.
  last: Rendered | null = null;
  lastDone = false;
  /// The passes of a render to `image.target_error` so far (the last one the job's), as the
  /// CLI renders them (src/render/target.rs): each from the first sample, the next one's
  /// samples from the last one's estimate; empty where the scene targets no error.
  passes: TargetPass[] = [];
  private panel: Panel;
  /// The environment maps loaded, by `environment.file`'s value; the built-in ones on their
  /// way.
  private maps = new Map<string, EnvironmentMap>();
  private fetching = new Set<string>();
  /// The name of the scene's file (as the messages name it).
  private sourceName = 'scene.toml';
  /// The CRC-32 of a map the page has, by `environment.file`'s value (SceneLoader.build's).
  private checksums: MapChecksums = (file) => this.maps.get(file)?.checksum ?? builtinChecksum(file);

  constructor(private tracer: Tracer) {
    this.scene = loadScene('');
    this.home = this.scene;
    this.panel = new Panel($('panel'), (path, value) => this.edit(path, value));
    void this.run();
  }

  /// The scene text `text`, loaded as the file `name`; the CLI's line where it is bad.
  loadText(toml: string, name = 'scene.toml'): string | null {
    try {
      const s = loadScene(toml, name, this.checksums);
      text.value = toml;
      this.sourceName = name;
      this.home = s;
      this.set(s, false);
      return null;
    } catch (e) {
      return this.refuse(e);
    }
  }

  /// Shows the error line of a bad scene (and returns it).
  private refuse(e: unknown): string {
    if (!(e instanceof SceneError)) throw e;
    error.textContent = `error: ${e.message}`;
    return e.message;
  }

  /// A new scene to show; `rewrite` puts its full TOML in the text box.
  set(s: Scene, rewrite: boolean): void {
    this.scene = s;
    error.textContent = '';
    if (rewrite) text.value = sceneToToml(s);
    this.panel.show(s);
    this.askForMap();
    this.kick();
  }

  /// The scene's environment map, where the page has it.
  private mapOf(s: Scene): EnvironmentMap | null {
    const file = s.get('environment.file') as string;
    return file === '' ? null : (this.maps.get(file) ?? null);
  }

  /// Starts fetching a built-in map the scene names, or shows the file picker for any other it
  /// does not have yet.
  private askForMap(): void {
    const file = this.scene.get('environment.file') as string;
    const builtin = file.startsWith(BUILTIN_PREFIX);
    envPrompt.hidden = file === '' || builtin || this.maps.has(file);
    envName.textContent = file;
    if (!builtin || this.maps.has(file) || this.fetching.has(file)) return;
    this.fetching.add(file);
    const name = file.slice(BUILTIN_PREFIX.length);
    void fetch(BUILTIN_URLS[name])
      .then(async (r) => {
        if (!r.ok) throw new Error(`fetching it gave HTTP ${r.status}`);
        return loadMap(new Uint8Array(await r.arrayBuffer()), mapFormat(name) as MapFormat);
      })
      .then(
        (map) => this.keepMap(file, map),
        (e: unknown) => (error.textContent = `error: environment.file ${file}: ${e instanceof Error ? e.message : e}`),
      )
      .finally(() => {
        this.fetching.delete(file);
        this.kick();
      });
  }

  private keepMap(file: string, map: EnvironmentMap): void {
    this.maps.delete(file);
    this.maps.set(file, map);
    while (this.maps.size > MAPS_KEPT) this.maps.delete(this.maps.keys().next().value!);
    notice.textContent = mapNotice(map, file) ?? '';
  }

  /// The file the picker gave for the scene's map: decoded and packed, then the scene loaded
  /// again, so that its checksum is verified or recorded as the CLI's loader does.
  async pickMap(bytes: Uint8Array): Promise<string | null> {
    const file = this.scene.get('environment.file') as string;
    const format = mapFormat(file) as MapFormat;
    try {
      this.keepMap(file, await loadMap(bytes, format));
    } catch (e) {
      error.textContent = `error: ${this.sourceName}: environment.file = ${JSON.stringify(file)}: ${e instanceof Error ? e.message : e}`;
      return error.textContent;
    }
    const loader = new SceneLoader();
    loader.tomlStr(sceneToToml(this.scene), { kind: 'file', path: this.sourceName });
    try {
      this.set(loader.build(this.checksums), false);
      return null;
    } catch (e) {
      this.maps.delete(file);
      this.askForMap();
      this.kick();
      return this.refuse(e);
    }
  }

  /// What the status line says of the scene's map where it is not there yet.
  private mapStatus(s: Scene): string {
    const file = s.get('environment.file') as string;
    if (file === '' || this.twoD || this.maps.has(file)) return '';
    const without = s.get('shading.model') === 'path' ? 'the gradient sky' : 'the flat background';
    const doing = this.fetching.has(file) ? 'loading' : 'not loaded (choose its file below)';
    return `; environment map ${file} ${doing}: rendering ${without} meanwhile`;
  }

  /// The panel's edit of one key, checked as `--set KEY=VALUE` over the scene.
  private edit(path: string, value: string): void {
    const loader = new SceneLoader();
    let base = this.scene;
    if (path === 'fractal.algebra') {
      // As the desktop explorer does: c and the slice cut or padded to the new dimension.
      base = new Map(this.scene);
      setAlgebra(base, JSON.parse(value));
    }
    if (path === 'environment.file') {
      // A map named anew records its own checksum, as a `--set` of the file over a scene does.
      base = new Map(base);
      base.set('environment.checksum', 0);
    }
    loader.tomlStr(sceneToToml(base), { kind: 'default' });
    try {
      loader.set(`${path}=${value}`);
      this.set(loader.build(this.checksums), true);
    } catch (e) {
      this.refuse(e);
      this.panel.show(this.scene);
    }
  }

  /// A move of the view (camera or 2D view), refused where f32 would stop resolving it.
  move(change: (s: Scene) => void): void {
    const s = new Map(this.scene);
    change(s);
    const warn = this.twoD ? julia2dWarnings : sliceWarnings;
    const before = new Set(warn(this.scene));
    const added = warn(s).filter((w) => !before.has(w));
    if (added.length > 0) {
      notice.textContent =
        `The page stops zooming here: WebGPU has no f64, and f32 stops resolving the view ` +
        `(${added[0].replace(/; use --precision f64.*$/, '')}). The native app goes on in f64.`;
      return;
    }
    notice.textContent = '';
    this.lastMove = performance.now();
    this.set(s, true);
  }

  resetView(): void {
    this.move((s) => {
      for (const k of ['camera.eye', 'camera.target', 'camera.up', 'camera.fov_y_degrees', 'view2d.center', 'view2d.extent']) {
        s.set(k, structuredClone(this.home.get(k)!));
      }
    });
  }

  setMode(twoD: boolean): void {
    this.twoD = twoD;
    modeMenu.value = twoD ? '2d' : '3d';
    this.kick();
  }

  kick(): void {
    this.pending = true;
    const w = this.wake;
    this.wake = null;
    w?.();
  }

  /// Resolves once the view shows the whole scene with every sample.
  idle(): Promise<void> {
    if (!this.pending && this.wake !== null) return Promise.resolve();
    return new Promise((ok) => this.idleWaiters.push(ok));
  }

  private moving(): boolean {
    return performance.now() - this.lastMove < SETTLE_MS;
  }

  private async run(): Promise<void> {
    for (;;) {
      this.pending = false;
      let more = false;
      try {
        more = await this.frame();
      } catch (e) {
        error.textContent = `error: ${e instanceof Error ? e.message : String(e)}`;
        this.job = null;
        this.jobKey = '';
      }
      if (!more && !this.pending) {
        // Idle once the picture is whole: with its map, where a built-in one is on its way.
        if (this.fetching.size === 0) this.idleWaiters.splice(0).forEach((ok) => ok());
        await new Promise<void>((ok) => (this.wake = ok));
      } else {
        await new Promise((ok) => requestAnimationFrame(ok));
      }
    }
  }

  /// One step of the view: a new job where the scene or the mode changed, else the next
  /// dispatch of samples, then the picture shown. Whether there is more to do.
  private async frame(): Promise<boolean> {
    const moving = this.moving();
    const target = moving ? movingScene(this.scene) : this.scene;
    const map = this.mapOf(target);
    const key = `${this.twoD ? '2d' : '3d'}\n${map === null ? 'no map' : 'map'}\n${sceneToToml(target)}`;
    const targeting = !this.twoD && targetsError(target);
    if (key !== this.jobKey) {
      this.jobKey = key;
      const most = target.get('image.samples') as number;
      this.passes = targeting ? [{ samples: Math.min(most, FIRST_PASS), estimated_relative_rmse: null }] : [];
      await this.startJob(targeting ? passScene(target, this.passes[0].samples) : target, map?.packed ?? null);
    }
    const job = this.job!;
    if (job.done) return moving;
    job.step();
    const r = await job.read();
    if (this.job !== job) return true;
    const pass = this.passes.at(-1);
    if (targeting && pass !== undefined && job.done) {
      // A pass is whole: the render stops at the target or at image.samples, else the next
      // pass starts from the first sample with the samples this one's estimate asks for.
      const e = r.estimate?.relative ?? null;
      pass.estimated_relative_rmse = e;
      const [goal, most] = [target.get('image.target_error') as number, target.get('image.samples') as number];
      if (!(e !== null && e <= goal) && pass.samples < most) {
        const samples = nextSamples(pass.samples, e, goal, most);
        this.passes.push({ samples, estimated_relative_rmse: null });
        this.show(r, target);
        await this.startJob(passScene(target, samples), map?.packed ?? null);
        return true;
      }
    }
    this.show(r, target);
    if (!moving) {
      this.last = r;
      this.lastDone = job.done;
    }
    return !job.done || moving;
  }

  /// Replaces the job with a new one rendering `s`.
  private async startJob(s: Scene, packed: Float32Array<ArrayBuffer> | null): Promise<void> {
    this.job?.destroy();
    this.job = null;
    this.lastDone = false;
    this.job = await this.tracer.start(s, this.twoD, packed);
  }

  /// Shows a render in the canvas: the tracer's 0xFFBBGGRR pixels are RGBA bytes as they are;
  /// a step or samples view is the heat map the CLI draws of them.
  private show(r: Rendered, s: Scene): void {
    canvas.width = r.width;
    canvas.height = r.height;
    const frame = $<HTMLDivElement>('frame');
    frame.style.aspectRatio = `${s.get('image.width')} / ${s.get('image.height')}`;
    const view = this.twoD ? 'shaded' : (s.get('image.view') as string);
    const bytes = new Uint8ClampedArray(4 * r.width * r.height);
    let heat: HeatMap | null = null;
    if (view === 'steps') heat = stepsView(r.steps, r.width, r.height);
    else if (view === 'divergence') heat = divergenceView(r.steps, r.width, r.height);
    else if (view === 'samples') heat = samplesView(samplesOf(r), r.width, r.height);
    if (heat === null) {
      bytes.set(new Uint8Array(r.colour.buffer, r.colour.byteOffset, r.colour.byteLength));
    } else {
      for (let k = 0; k < r.width * r.height; k++) {
        bytes.set(heat.rgb.subarray(3 * k, 3 * k + 3), 4 * k);
        bytes[4 * k + 3] = 255;
      }
    }
    showLegend(heat);
    canvas.getContext('2d')!.putImageData(new ImageData(bytes, r.width, r.height), 0, 0);
    const sampling = r.samples > 1 ? `, samples ${r.taken}/${r.samples}` : '';
    const error = r.estimate === null ? '' : `, error ${(100 * r.estimate.relative).toFixed(1)}%`;
    const goal = s.get('image.target_error') as number;
    const passes = this.passes.length > 0 ? `, pass ${this.passes.length} to ${(100 * goal).toFixed(1)}%` : '';
    status.textContent =
      `WebGPU: ${this.tracer.adapterName}; ${r.width}x${r.height}${sampling}${error}${passes}, ` +
      `${r.milliseconds.toFixed(0)} ms${this.moving() ? ' (moving: half resolution)' : ''}${this.mapStatus(s)}`;
  }

  /// The scene as a PNG of the view (the picture shown) with the scene's qjulia-scene chunk.
  async png(): Promise<Uint8Array<ArrayBuffer>> {
    await this.idle();
    const blob = await new Promise<Blob | null>((ok) => canvas.toBlob(ok, 'image/png'));
    if (blob === null) throw new Error('the canvas gave no PNG');
    const png = withScene(new Uint8Array(await blob.arrayBuffer()), sceneToToml(this.scene));
    // Where the picture has an estimate, its qjulia-error chunk, as `render` writes it.
    const r = this.last;
    if (r === null || !this.lastDone || r.estimate === null) return png;
    const pass = this.passes.at(-1);
    const goal = this.scene.get('image.target_error') as number;
    const met = pass?.estimated_relative_rmse != null && pass.estimated_relative_rmse <= goal;
    const target = pass === undefined ? null : { stopped_by: met ? 'target_error' : 'samples', samples: pass.samples };
    return withText(png, ERROR_PNG_KEYWORD, errorText(r.estimate.rmse, r.estimate.relative, target));
  }
}

function showLegend(heat: HeatMap | null): void {
  const legend = $<HTMLDivElement>('legend');
  legend.style.display = heat === null ? 'none' : 'block';
  if (heat === null) return;
  const stops = COLOUR_STOPS.map(([r, g, b], k) => `rgb(${r},${g},${b}) ${(100 * k) / (COLOUR_STOPS.length - 1)}%`);
  legend.querySelector<HTMLDivElement>('.bar')!.style.background = `linear-gradient(to right, ${stops.join(', ')})`;
  const ticks = legend.querySelectorAll('.ticks span');
  [heat.legend.min, heat.legend.mid, heat.legend.max].forEach((v, k) => (ticks[k].textContent = String(v)));
  legend.querySelector('.title')!.textContent = heat.legend.title;
}

/// Downloads bytes or text as a file.
function download(name: string, data: BlobPart, type: string): void {
  const url = URL.createObjectURL(new Blob([data], { type }));
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}

/// The mouse, touch and wheel on the view, as the desktop explorer's (src/explore/input.rs):
/// left drag orbits, right, middle or shift drag pans, the wheel zooms; two fingers pinch to
/// zoom and move to pan. In 2D mode a drag pans and the wheel zooms about the pointer.
function pointer(x: Explorer): void {
  const down = new Map<number, { x: number; y: number; pan: boolean }>();
  const widest = SCHEMA.keys.find((k) => k.path === 'view2d.extent')!.slider!.max;
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('pointerdown', (e) => {
    canvas.setPointerCapture(e.pointerId);
    down.set(e.pointerId, { x: e.clientX, y: e.clientY, pan: e.button !== 0 || e.shiftKey });
    canvas.focus();
  });
  const up = (e: PointerEvent) => down.delete(e.pointerId);
  canvas.addEventListener('pointerup', up);
  canvas.addEventListener('pointercancel', up);
  canvas.addEventListener('pointermove', (e) => {
    const p = down.get(e.pointerId);
    if (p === undefined) return;
    const rect = canvas.getBoundingClientRect();
    if (down.size === 2) {
      // A pinch: the change in the fingers' distance zooms, their midpoint's move pans.
      const [a, b] = [...down.values()];
      const before = Math.hypot(a.x - b.x, a.y - b.y);
      const [mx, my] = [(a.x + b.x) / 2, (a.y + b.y) / 2];
      p.x = e.clientX;
      p.y = e.clientY;
      const after = Math.hypot(a.x - b.x, a.y - b.y);
      const [dx, dy] = [(a.x + b.x) / 2 - mx, (a.y + b.y) / 2 - my];
      const scroll = Math.log(after / Math.max(before, 1)) / camera.ZOOM_PER_POINT;
      x.move((s) => {
        if (x.twoD) {
          const v = camera.view2dOf(s);
          camera.drag2d(v, dx, dy, rect.width);
          camera.wheelZoom2d(v, scroll, rect.width, null, widest);
          camera.setView2d(s, v);
        } else {
          const c = camera.cameraOf(s);
          camera.dragPan(c, dx, dy, rect.height);
          camera.wheelZoom(c, scroll);
          camera.setCamera(s, c);
        }
      });
      return;
    }
    const [dx, dy] = [e.clientX - p.x, e.clientY - p.y];
    p.x = e.clientX;
    p.y = e.clientY;
    if (dx === 0 && dy === 0) return;
    x.move((s) => {
      if (x.twoD) {
        const v = camera.view2dOf(s);
        camera.drag2d(v, dx, dy, rect.width);
        camera.setView2d(s, v);
      } else {
        const c = camera.cameraOf(s);
        if (p.pan) camera.dragPan(c, dx, dy, rect.height);
        else camera.dragOrbit(c, dx, dy);
        camera.setCamera(s, c);
      }
    });
  });
  canvas.addEventListener(
    'wheel',
    (e) => {
      e.preventDefault();
      const lines = e.deltaMode === WheelEvent.DOM_DELTA_LINE ? 16 : e.deltaMode === WheelEvent.DOM_DELTA_PAGE ? 400 : 1;
      const scroll = -e.deltaY * lines;
      const rect = canvas.getBoundingClientRect();
      const at: [number, number] = [e.clientX - (rect.left + rect.width / 2), e.clientY - (rect.top + rect.height / 2)];
      x.move((s) => {
        if (x.twoD) {
          const v = camera.view2dOf(s);
          camera.wheelZoom2d(v, scroll, rect.width, at, widest);
          camera.setView2d(s, v);
        } else {
          const c = camera.cameraOf(s);
          camera.wheelZoom(c, scroll);
          camera.setCamera(s, c);
        }
      });
    },
    { passive: false },
  );
  canvas.addEventListener('keydown', (e) => {
    if (e.key === 'r' || e.key === 'R') x.resetView();
    const factor = e.key === '+' || e.key === '=' ? 0.9 : e.key === '-' ? 1 / 0.9 : 0;
    if (factor === 0) return;
    x.move((s) => {
      if (x.twoD) {
        const v = camera.view2dOf(s);
        v.extent = camera.clampExtent(v.extent * factor, widest);
        camera.setView2d(s, v);
      } else {
        const c = camera.cameraOf(s);
        camera.zoom(c, factor);
        camera.setCamera(s, c);
      }
    });
  });
}

async function start(): Promise<void> {
  const tracer = await Tracer.create();
  if (typeof tracer === 'string') {
    status.innerHTML = `${tracer}: the page needs WebGPU (Chrome or Edge 113+, Safari 26, Firefox 141+ on Windows). Use the <a href="${NATIVE}">native build</a>.`;
    return;
  }
  tracer.device.lost.then((info) => {
    status.textContent = `the WebGPU device was lost (${info.message}); reload the page`;
  });
  const x = new Explorer(tracer);
  pointer(x);
  for (const p of SCHEMA.presets) presetMenu.append(new Option(p.name, p.slug));
  presetMenu.addEventListener('change', () => {
    const p = SCHEMA.presets.find((q) => q.slug === presetMenu.value);
    if (p === undefined) return;
    const loader = new SceneLoader();
    loader.tomlStr(p.toml, { kind: 'preset', slug: p.slug } as Source);
    const s = loader.build();
    x.loadText(sceneToToml(s), `preset ${p.slug}`);
    x.setMode(p.two_d);
  });
  modeMenu.addEventListener('change', () => x.setMode(modeMenu.value === '2d'));
  $('home').addEventListener('click', () => x.resetView());
  $('render').addEventListener('click', () => x.loadText(text.value));
  // A share link: this page with the scene's TOML in the fragment, which the page opens.
  $('share').addEventListener('click', () => {
    location.hash = encodeURIComponent(text.value);
    void navigator.clipboard?.writeText(location.href).catch(() => undefined);
  });
  $('save').addEventListener('click', () => download('scene.toml', sceneToToml(x.scene), 'text/plain'));
  $('export').addEventListener('click', async () => download('qjulia.png', await x.png(), 'image/png'));
  envFile.addEventListener('change', async () => {
    const f = envFile.files?.[0];
    if (f === undefined) return;
    envFile.value = '';
    await x.pickMap(new Uint8Array(await f.arrayBuffer()));
  });
  const file = $<HTMLInputElement>('file');
  $('open').addEventListener('click', () => file.click());
  file.addEventListener('change', async () => {
    const f = file.files?.[0];
    if (f === undefined) return;
    file.value = '';
    await openFile(x, f.name, new Uint8Array(await f.arrayBuffer()));
  });

  const plain = (r: Rendered) => ({
    width: r.width,
    height: r.height,
    colour: [...r.colour],
    depth: [...r.depth].map((d) => (Number.isNaN(d) ? null : d)),
    steps: [...r.steps],
    samples: r.samples,
    estimate: r.estimate,
    passes: x.passes.map((p) => ({ ...p })),
  });
  const shown = async () => {
    await x.idle();
    return x.last === null ? null : plain(x.last);
  };
  (window as unknown as { qjulia: unknown }).qjulia = {
    adapter: tracer.adapterName,
    /// Loads TOML and waits for the whole picture; its pixels (colour, depth, steps as plain
    /// arrays), or the error line.
    async render(toml: string) {
      const why = x.loadText(toml);
      return why !== null ? { error: why } : await shown();
    },
    /// The picture shown once the view is still (the share link's, once the page has opened it).
    last: shown,
    /// The scene text in the text box, and the scene shown as the full TOML Save writes.
    text: () => text.value,
    scene: () => sceneToToml(x.scene),
    /// A file opened as the Open button opens it (its name, its bytes as base64).
    open: (name: string, base64: string) => openFile(x, name, Uint8Array.from(atob(base64), (c) => c.charCodeAt(0))),
    /// The PNG Export writes, as base64.
    async png() {
      const bytes = await x.png();
      let s = '';
      for (const b of bytes) s += String.fromCharCode(b);
      return btoa(s);
    },
    mode: (twoD: boolean) => x.setMode(twoD),
    /// An environment map's file given to the picker (its bytes as base64).
    pickMap: (base64: string) => x.pickMap(Uint8Array.from(atob(base64), (c) => c.charCodeAt(0))),
    /// The status line, the map prompt's text where it shows.
    status: () => status.textContent,
    prompt: () => (envPrompt.hidden ? null : envPrompt.textContent),
    error: () => error.textContent,
    notice: () => notice.textContent,
  };
  const fragment = decodeURIComponent(location.hash.slice(1));
  x.loadText(fragment);
  await x.idle();
  document.body.dataset.ready = 'true';
}

/// Opens a scene file: TOML, or a PNG carrying a qjulia scene; a bad one gets the CLI's line,
/// naming the file.
async function openFile(x: Explorer, name: string, bytes: Uint8Array): Promise<string | null> {
  let toml: string;
  if (name.toLowerCase().endsWith('.png')) {
    let found: string | null = null;
    try {
      found = await sceneOf(bytes);
    } catch (e) {
      found = null;
      error.textContent = `error: ${name}: ${e instanceof Error ? e.message : String(e)}`;
      return error.textContent;
    }
    if (found === null) {
      error.textContent = `error: ${name}: holds no qjulia scene (no qjulia-scene iTXt chunk)`;
      return error.textContent;
    }
    toml = found;
  } else {
    toml = new TextDecoder().decode(bytes);
  }
  return x.loadText(toml, name);
}

void start();
