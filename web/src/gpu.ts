// The page's GPU host: the kernels of shaders/ on WebGPU, as the Rust host runs them
// (src/gpu/tracer.rs, src/gpu/path.rs, src/gpu/julia2d.rs and src/gpu/kernel/): the bind layout
// of the Rust runner (binding 0 the uniform, 1.. the outputs colour, depth, steps, work,
// accumulated, aovs; the path tracer's own uniform at 7; the environment map at 8, read-only,
// or a placeholder of 16 zero bytes where there is none), one module per kernel and the scene
// features a variant leaves on, one pipeline per module and the variant's other override
// constants (both cached, as the Rust side caches them), the samples added dispatch by
// dispatch with the uniforms of src/uniform.ts, the running mean kept in `accumulated` between
// them. A render is a [`Job`]: the explorer adds a dispatch of samples a frame and shows what
// is there (idle accumulation), and reads it back as the CLI's frame.

import { Display } from './display';
import { type ErrorEstimate, rawEstimate } from './estimate';
import type { Scene } from './scene';
import { kernel as composeKernel, splitConstants } from './shaders';
import {
  type Dispatch,
  JULIA2D_LAYOUT,
  PARAMS_LAYOUT,
  PATH_LAYOUT,
  overrides,
  packJulia2d,
  packParams,
  packPath,
  pathSamplesPerDispatch,
  samplesPerDispatch,
} from './uniform';

/// Bytes a pixel of each output (TRACE_OUTPUTS of src/gpu/mod.rs, bytes_per_item times planes:
/// the accumulator keeps adaptive sampling's streams in three more planes, and only its first
/// comes back); the AOVs (the last) are a placeholder of one pixel, as the Rust runner binds
/// them when not read.
const OUTPUT_BYTES = [4, 4, 4, 16, 64, 64];
const ON_DEMAND = [false, false, false, false, false, true];
/// The 2D view's outputs: colour, the in-set marker, iterations (JULIA2D_KERNEL).
const JULIA2D_OUTPUT_BYTES = [4, 4, 4];
/// Invocations per workgroup in x and y (WORKGROUP_SIZE).
const WORKGROUP = 8;
/// Camera rays an invocation of the path tracer traces together (DEFAULT_PATH_INTERLEAVE of
/// src/gpu/variant.rs; the tracer's `main` keeps the shader's default, DEFAULT_INTERLEAVE = 2).
const PATH_INTERLEAVE = 1;
/// The environment map's binding (shaders/environment.wgsl), a read-only storage buffer.
const ENVIRONMENT_BINDING = 8;

export interface Rendered {
  width: number;
  height: number;
  /// 0xFFBBGGRR per pixel, as the CLI's frame packs it (path mode: the display transform of
  /// the linear mean).
  colour: Uint32Array;
  /// The hit's t; NaN where the ray missed (2D: 0 in the set, NaN outside).
  depth: Float32Array;
  steps: Uint32Array;
  /// Path mode and adaptive sampling: the accumulator (linear mean RGB, then the pixel's
  /// state: M2 while it samples, minus its samples once done), else null.
  accumulated: Float32Array<ArrayBuffer> | null;
  /// Path mode at two samples or more: the image's estimated error from its pixels' halves
  /// (src/estimate.ts, `--stats`' `estimated_rmse`); with adaptive sampling only once every
  /// pixel is done (until then a pixel's streams hold its state where the halves go). Else null.
  estimate: ErrorEstimate | null;
  /// Samples taken so far (of `samples`).
  taken: number;
  samples: number;
  /// Milliseconds from the job's first dispatch to this readback mapped.
  milliseconds: number;
}

/// Why this browser cannot run the page, or null.
export function noWebGpu(): string | null {
  return 'gpu' in navigator ? null : 'this browser has no WebGPU (navigator.gpu)';
}

type Kind = 'trace' | 'path' | 'julia2d';

interface Kernel {
  /// Its name in shaders/kernels.json.
  name: string;
  /// Its text composed for each set of scene features (joined by spaces), as a module.
  modules: Map<string, GPUShaderModule>;
  entryPoint: string;
  layout: GPUBindGroupLayout;
  pipelineLayout: GPUPipelineLayout;
}

/// A render in progress: the scene's buffers, its pipeline, and the samples added so far.
export class Job {
  taken = 0;
  readonly samples: number;
  readonly perDispatch: number;
  private started = 0;

  constructor(
    private tracer: Tracer,
    readonly scene: Scene,
    readonly kind: Kind,
    private pipeline: GPUComputePipeline,
    private uniform: GPUBuffer,
    private outputs: GPUBuffer[],
    private bindGroup: GPUBindGroup,
    readonly width: number,
    readonly height: number,
    /// Whether the environment map is bound (the uniform's env_map).
    private envMap: boolean,
  ) {
    this.samples = kind === 'julia2d' ? 1 : Math.max(scene.get('image.samples') as number, 1);
    const perDispatch = samplesPerDispatch(height, width, this.samples);
    this.perDispatch =
      kind === 'path'
        ? Math.min(
            perDispatch,
            pathSamplesPerDispatch(
              scene.get('path.bounces') as number,
              scene.get('fractal.max_steps') as number,
              envMap,
            ),
          )
        : perDispatch;
  }

  get done(): boolean {
    return this.taken >= this.samples;
  }

  /// Queues the next dispatch of samples (the whole image as one band).
  step(): void {
    if (this.done) return;
    if (this.taken === 0) this.started = performance.now();
    const device = this.tracer.device;
    const d: Dispatch = {
      rowOffset: 0,
      rowCount: this.height,
      rowStride: this.width,
      outRow: 0,
      sampleStart: this.taken,
      sampleEnd: Math.min(this.taken + this.perDispatch, this.samples),
    };
    const bytes = this.kind === 'julia2d' ? packJulia2d(this.scene, d) : packParams(this.scene, d, this.envMap);
    device.queue.writeBuffer(this.uniform, 0, bytes);
    const encoder = device.createCommandEncoder();
    const pass = encoder.beginComputePass();
    pass.setPipeline(this.pipeline);
    pass.setBindGroup(0, this.bindGroup);
    pass.dispatchWorkgroups(Math.ceil(this.width / WORKGROUP), Math.ceil(this.height / WORKGROUP));
    pass.end();
    device.queue.submit([encoder.finish()]);
    this.taken = d.sampleEnd;
  }

  /// What the job holds now, read back: colour, depth and steps (and the accumulator where
  /// path mode or adaptive sampling needs it).
  async read(): Promise<Rendered> {
    const device = this.tracer.device;
    const pixels = this.width * this.height;
    const wantsMean = this.kind === 'path' || this.adaptive;
    // Path mode reads the halves too: the accumulator's second and third planes, after the first.
    const planes = this.kind === 'path' ? 3 : wantsMean ? 1 : 0;
    const read = device.createBuffer({
      size: (12 + 16 * planes) * pixels,
      usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST,
    });
    const encoder = device.createCommandEncoder();
    for (let k = 0; k < 3; k++) encoder.copyBufferToBuffer(this.outputs[k], 0, read, 4 * k * pixels, 4 * pixels);
    if (planes > 0) encoder.copyBufferToBuffer(this.outputs[4], 0, read, 12 * pixels, 16 * planes * pixels);
    device.queue.submit([encoder.finish()]);
    await read.mapAsync(GPUMapMode.READ);
    const bytes = read.getMappedRange().slice(0);
    read.unmap();
    read.destroy();
    const milliseconds = performance.now() - this.started;
    const depth = new Float32Array(bytes, 4 * pixels, pixels).map((d) => (d < 0 ? NaN : d));
    const accumulated = wantsMean ? new Float32Array(bytes, 12 * pixels, 4 * pixels) : null;
    let colour: Uint32Array = new Uint32Array(bytes, 0, pixels);
    if (this.kind === 'path') {
      const display = new Display(this.scene.get('image.exposure') as number, this.scene.get('image.tone_map') as string);
      colour = display.packAll(accumulated!);
    }
    const halved = this.kind === 'path' && this.samples > 1 && (!this.adaptive || this.done);
    const estimate = halved ? rawEstimate(new Float32Array(bytes, 12 * pixels, 12 * pixels), this.width) : null;
    return {
      width: this.width,
      height: this.height,
      colour,
      depth,
      steps: new Uint32Array(bytes, 8 * pixels, pixels),
      accumulated,
      estimate,
      taken: this.taken,
      samples: this.samples,
      milliseconds,
    };
  }

  private get adaptive(): boolean {
    return (this.scene.get('path.noise_target') as number) > 0 && this.samples > 1;
  }

  /// Frees the job's buffers.
  destroy(): void {
    [this.uniform, ...this.outputs].forEach((b) => b.destroy());
  }
}

export class Tracer {
  private pipelines = new Map<string, Promise<GPUComputePipeline>>();
  private kernels: Record<Kind, Kernel>;
  /// Binding 8 where no map is bound: the kernels read nothing of it.
  private placeholder: GPUBuffer;
  /// The last environment map uploaded, by its packed floats.
  private map: { packed: Float32Array<ArrayBuffer>; buffer: GPUBuffer } | null = null;

  private constructor(
    public device: GPUDevice,
    public adapterName: string,
  ) {
    const storage = (binding: number): GPUBindGroupLayoutEntry => ({
      binding,
      visibility: GPUShaderStage.COMPUTE,
      buffer: { type: 'storage' },
    });
    const uniform = (binding: number): GPUBindGroupLayoutEntry => ({
      binding,
      visibility: GPUShaderStage.COMPUTE,
      buffer: { type: 'uniform' },
    });
    const kernel = (name: string, entryPoint: string, entries: GPUBindGroupLayoutEntry[]): Kernel => {
      const layout = device.createBindGroupLayout({ label: name, entries });
      return {
        name,
        modules: new Map(),
        entryPoint,
        layout,
        pipelineLayout: device.createPipelineLayout({ bindGroupLayouts: [layout] }),
      };
    };
    const environment: GPUBindGroupLayoutEntry = {
      binding: ENVIRONMENT_BINDING,
      visibility: GPUShaderStage.COMPUTE,
      buffer: { type: 'read-only-storage' },
    };
    const traceEntries = [uniform(0), ...OUTPUT_BYTES.map((_, k) => storage(1 + k))];
    this.kernels = {
      trace: kernel('trace', 'main', [...traceEntries, environment]),
      path: kernel('path', 'path_main', [...traceEntries, uniform(7), environment]),
      julia2d: kernel('julia2d', 'main', [uniform(0), storage(1), storage(2), storage(3)]),
    };
    this.placeholder = device.createBuffer({ size: 16, usage: GPUBufferUsage.STORAGE });
  }

  /// The buffer binding 8 takes for `packed` (the map's floats, src/envmap.ts), uploaded at its
  /// first use and kept while it is the last one; the placeholder for null.
  private environmentBuffer(packed: Float32Array<ArrayBuffer> | null): GPUBuffer {
    if (packed === null) return this.placeholder;
    if (this.map?.packed !== packed) {
      this.map?.buffer.destroy();
      const buffer = this.device.createBuffer({
        size: packed.byteLength,
        usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_DST,
      });
      this.device.queue.writeBuffer(buffer, 0, packed);
      this.map = { packed, buffer };
    }
    return this.map.buffer;
  }

  /// The tracer on the browser's adapter; a string says why there is none.
  static async create(): Promise<Tracer | string> {
    const why = noWebGpu();
    if (why !== null) return why;
    const adapter = await navigator.gpu.requestAdapter();
    if (adapter === null) return 'WebGPU found no adapter';
    const device = await adapter.requestDevice();
    const info = adapter.info;
    return new Tracer(device, `${info.vendor} ${info.architecture} ${info.description}`.trim());
  }

  /// The kernel a scene's picture needs: the 2D view, the path tracer or the tracer.
  static kindOf(scene: Scene, twoD: boolean): Kind {
    if (twoD) return 'julia2d';
    return scene.get('shading.model') === 'path' ? 'path' : 'trace';
  }

  /// The pipeline of a kernel and a scene's variant (`envMap`: with its environment map bound),
  /// built on first use and kept: the kernel composed for the scene features the variant leaves
  /// on, with the rest of its override constants.
  pipeline(kind: Kind, scene: Scene, envMap: boolean): Promise<GPUComputePipeline> {
    const split = splitConstants(kind === 'julia2d' ? [] : overrides(scene, envMap));
    const constants: Record<string, number> = Object.fromEntries(split.left);
    if (kind === 'path') constants.INTERLEAVE = PATH_INTERLEAVE;
    const features = split.on.join(' ');
    const key = `${kind} ${features} ${JSON.stringify(constants)}`;
    let made = this.pipelines.get(key);
    if (made === undefined) {
      const k = this.kernels[kind];
      let module = k.modules.get(features);
      if (module === undefined) {
        module = this.device.createShaderModule({ label: `${kind} ${features}`, code: composeKernel(k.name, split.on) });
        k.modules.set(features, module);
      }
      made = this.device.createComputePipelineAsync({
        label: key,
        layout: k.pipelineLayout,
        compute: { module, entryPoint: k.entryPoint, constants },
      });
      this.pipelines.set(key, made);
    }
    return made;
  }

  /// A new render of a validated scene (its image.width x image.height), nothing dispatched;
  /// `environment`: its map's packed floats (src/envmap.ts), or null where the page has none
  /// (the gradient sky, the flat background).
  async start(scene: Scene, twoD = false, environment: Float32Array<ArrayBuffer> | null = null): Promise<Job> {
    const kind = Tracer.kindOf(scene, twoD);
    const width = scene.get('image.width') as number;
    const height = scene.get('image.height') as number;
    const pixels = width * height;
    const envMap = kind !== 'julia2d' && environment !== null;
    const pipeline = await this.pipeline(kind, scene, envMap);
    const device = this.device;
    const layout = kind === 'julia2d' ? JULIA2D_LAYOUT : PARAMS_LAYOUT;
    const uniform = device.createBuffer({
      size: layout.size,
      usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST,
    });
    const sizes = kind === 'julia2d' ? JULIA2D_OUTPUT_BYTES : OUTPUT_BYTES;
    const outputs = sizes.map((bytes, k) =>
      device.createBuffer({
        size: bytes * (kind !== 'julia2d' && ON_DEMAND[k] ? 1 : pixels),
        usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_SRC,
      }),
    );
    const entries: GPUBindGroupEntry[] = [uniform, ...outputs].map((buffer, binding) => ({
      binding,
      resource: { buffer },
    }));
    const owned = [...outputs];
    if (kind === 'path') {
      const path = device.createBuffer({
        size: PATH_LAYOUT.size,
        usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST,
      });
      device.queue.writeBuffer(path, 0, packPath(scene));
      entries.push({ binding: 7, resource: { buffer: path } });
      owned.push(path);
    }
    if (kind !== 'julia2d') {
      const buffer = this.environmentBuffer(envMap ? environment : null);
      entries.push({ binding: ENVIRONMENT_BINDING, resource: { buffer } });
    }
    const bindGroup = device.createBindGroup({ layout: this.kernels[kind].layout, entries });
    return new Job(this, scene, kind, pipeline, uniform, owned, bindGroup, width, height, envMap);
  }

  /// Traces the whole image of a validated scene, every sample, and reads it back.
  async render(scene: Scene, twoD = false, environment: Float32Array<ArrayBuffer> | null = null): Promise<Rendered> {
    const job = await this.start(scene, twoD, environment);
    while (!job.done) job.step();
    const r = await job.read();
    job.destroy();
    return r;
  }
}
