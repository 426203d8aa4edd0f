// The page's GPU host: the tracer kernel (shaders/trace.wgsl's `main`, f32) on WebGPU, as the
// Rust host runs it (src/gpu/tracer.rs and src/gpu/kernel/): the bind layout of the Rust
// runner (binding 0 the uniform, 1.. the outputs colour, depth, steps, estimates, accumulated,
// aovs), one pipeline per variant's override constants (cached, as the Rust side caches them),
// the samples added dispatch by dispatch with the uniform of src/uniform.ts, then colour, depth
// and steps read back.

import type { Scene } from './scene';
import { TRACE_MODULE } from './shaders';
import { firstDispatch, overrides, packParams, PARAMS_LAYOUT } from './uniform';

/// Bytes a pixel of each output (TRACE_OUTPUTS of src/gpu/mod.rs); the AOVs (the last) are a
/// placeholder of one pixel, as the Rust runner binds them when not read.
const OUTPUT_BYTES = [4, 4, 4, 4, 16, 48];
const ON_DEMAND = [false, false, false, false, false, true];
/// Invocations per workgroup in x and y (WORKGROUP_SIZE).
const WORKGROUP = 8;

export interface Rendered {
  width: number;
  height: number;
  /// 0xFFBBGGRR per pixel, as the tracer packs it.
  colour: Uint32Array;
  /// The hit's t; NaN where the ray missed.
  depth: Float32Array;
  steps: Uint32Array;
  /// Milliseconds from the first dispatch to the readback mapped.
  milliseconds: number;
}

/// Why this browser cannot run the page, or null.
export function noWebGpu(): string | null {
  return 'gpu' in navigator ? null : 'this browser has no WebGPU (navigator.gpu)';
}

export class Tracer {
  private pipelines = new Map<string, GPUComputePipeline>();
  private module: GPUShaderModule;
  private layout: GPUBindGroupLayout;
  private pipelineLayout: GPUPipelineLayout;

  private constructor(
    public device: GPUDevice,
    public adapterName: string,
  ) {
    this.module = device.createShaderModule({ label: 'trace', code: TRACE_MODULE });
    const entries: GPUBindGroupLayoutEntry[] = [
      { binding: 0, visibility: GPUShaderStage.COMPUTE, buffer: { type: 'uniform' } },
      ...OUTPUT_BYTES.map((_, k) => ({
        binding: 1 + k,
        visibility: GPUShaderStage.COMPUTE,
        buffer: { type: 'storage' as const },
      })),
    ];
    this.layout = device.createBindGroupLayout({ label: 'trace', entries });
    this.pipelineLayout = device.createPipelineLayout({ bindGroupLayouts: [this.layout] });
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

  /// The pipeline of a scene's variant, built on first use and kept.
  async pipeline(scene: Scene): Promise<GPUComputePipeline> {
    const constants = Object.fromEntries(overrides(scene));
    const key = JSON.stringify(constants);
    let made = this.pipelines.get(key);
    if (made === undefined) {
      made = await this.device.createComputePipelineAsync({
        label: `trace ${key}`,
        layout: this.pipelineLayout,
        compute: { module: this.module, entryPoint: 'main', constants },
      });
      this.pipelines.set(key, made);
    }
    return made;
  }

  /// Traces the whole image of a validated scene (one band) and reads it back.
  async render(scene: Scene): Promise<Rendered> {
    const width = scene.get('image.width') as number;
    const height = scene.get('image.height') as number;
    const samples = Math.max(scene.get('image.samples') as number, 1);
    const pixels = width * height;
    const pipeline = await this.pipeline(scene);
    const device = this.device;
    const uniform = device.createBuffer({
      size: PARAMS_LAYOUT.size,
      usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST,
    });
    const outputs = OUTPUT_BYTES.map((bytes, k) =>
      device.createBuffer({
        size: bytes * (ON_DEMAND[k] ? 1 : pixels),
        usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_SRC,
      }),
    );
    const bindGroup = device.createBindGroup({
      layout: this.layout,
      entries: [uniform, ...outputs].map((buffer, binding) => ({ binding, resource: { buffer } })),
    });
    const first = firstDispatch(scene);
    const perDispatch = first.sampleEnd;
    const start = performance.now();
    for (let s = 0; s < samples; s += perDispatch) {
      const d = { ...first, sampleStart: s, sampleEnd: Math.min(s + perDispatch, samples) };
      device.queue.writeBuffer(uniform, 0, packParams(scene, d));
      const encoder = device.createCommandEncoder();
      const pass = encoder.beginComputePass();
      pass.setPipeline(pipeline);
      pass.setBindGroup(0, bindGroup);
      pass.dispatchWorkgroups(Math.ceil(width / WORKGROUP), Math.ceil(height / WORKGROUP));
      pass.end();
      device.queue.submit([encoder.finish()]);
    }
    const read = device.createBuffer({
      size: 12 * pixels,
      usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST,
    });
    const encoder = device.createCommandEncoder();
    for (let k = 0; k < 3; k++) encoder.copyBufferToBuffer(outputs[k], 0, read, 4 * k * pixels, 4 * pixels);
    device.queue.submit([encoder.finish()]);
    await read.mapAsync(GPUMapMode.READ);
    const bytes = read.getMappedRange().slice(0);
    read.unmap();
    const milliseconds = performance.now() - start;
    [uniform, read, ...outputs].forEach((b) => b.destroy());
    const depth = new Float32Array(bytes, 4 * pixels, pixels).map((d) => (d < 0 ? NaN : d));
    return {
      width,
      height,
      colour: new Uint32Array(bytes, 0, pixels),
      depth,
      steps: new Uint32Array(bytes, 8 * pixels, pixels),
      milliseconds,
    };
  }
}
