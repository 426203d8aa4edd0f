// The tracer's uniform (`struct Params` of shaders/trace.wgsl, f32) and its pipeline's override
// constants for a scene: the TypeScript twin of TraceParams::new (src/params.rs, with the
// scene's camera frame, slice bounds, pixel angle and focus distance of src/scene/mod.rs),
// F::trace_uniform and Variant::of (src/gpu/variant.rs). Every value is worked out in f64 as the
// host does, then rounded to f32 where the field is f32; the layout (offsets, sizes, types) is
// the one `qjulia gpu-params --json` emits (src/generated/layout.json), which the Rust tests
// hold against naga's reflection of the WGSL. test/uniform.test.ts compares the bytes and the
// constants with the binary's for every scene of the corpus.

import layoutJson from './generated/layout.json';
import type { Scene } from './scene';
import { type V3, cross, dot, length3, normalize, sub, toRadians } from './vector';

export interface FieldLayout {
  name: string;
  offset: number;
  size: number;
  type: string;
  per_dispatch: boolean;
}

export interface Layout {
  name: string;
  size: number;
  align: number;
  fields: FieldLayout[];
}

const LAYOUTS = layoutJson as unknown as { params: Layout; path: Layout; julia2d: Layout };
export const PARAMS_LAYOUT = LAYOUTS.params;
/// `struct PathParams` of shaders/path_uniform.wgsl (binding 7).
export const PATH_LAYOUT = LAYOUTS.path;

/// `struct Julia2dParams` of shaders/julia2d.wgsl (the 2D view's uniform).
export const JULIA2D_LAYOUT = LAYOUTS.julia2d;

/// Samples a dispatch adds at most (MAX_SAMPLES_PER_DISPATCH of src/gpu/tracer.rs).
export const MAX_SAMPLES_PER_DISPATCH = 8;
/// Pixels per band of a streamed render (src/memory.rs's band_pixels()).
export const BAND_PIXELS = 1 << 22;
/// |z|^2 beyond which f32 stops the orbit, whatever the scene asks (Real::ESCAPE_LIMIT).
export const ESCAPE_LIMIT_F32 = 1e8;

/// `v` scaled to unit length, divided by its largest component first (params.rs's `unit`).
export function unit(v: number[]): number[] {
  const m = v.reduce((m, x) => Math.max(m, Math.abs(x)), 0);
  const w = m > 0 ? v.map((x) => x / m) : v;
  const n = Math.sqrt(w.reduce((s, x) => s + x * x, 0));
  return n > 0 ? w.map((x) => x / n) : [0, 0, 1];
}

/// The camera's frame and the tangent of half the vertical field of view (Scene::camera_frame).
export function cameraFrame(s: Scene): { forward: V3; right: V3; up: V3; tanHalfFovY: number } {
  const eye = s.get('camera.eye') as V3;
  const target = s.get('camera.target') as V3;
  const forward = normalize(sub(target, eye));
  const right = normalize(cross(forward, s.get('camera.up') as V3));
  const up = cross(right, forward);
  const tanHalfFovY = Math.tan(toRadians(s.get('camera.fov_y_degrees') as number) * 0.5);
  return { forward, right, up, tanHalfFovY };
}

/// The 3D ball the 4D bounding ball cuts out of the slice (Scene::slice_bounds).
export function sliceBounds(s: Scene): { center: V3; radiusSquared: number } {
  const w = s.get('slice.offset') as number[];
  const basis = ['slice.x', 'slice.y', 'slice.z'].map((k) => s.get(k) as number[]);
  const coords = basis.map((b) => dot(b, w));
  let off = 0;
  for (let k = 0; k < w.length; k++) {
    let along = 0;
    for (let a = 0; a < 3; a++) along += basis[a][k] * coords[a];
    const v = w[k] - along;
    off += v * v;
  }
  return {
    center: [-coords[0], -coords[1], -coords[2]],
    radiusSquared: (s.get('fractal.bounding_radius_squared') as number) - off,
  };
}

/// A pixel's footprint per unit of distance along the ray (Scene::pixel_angle).
export function pixelAngle(s: Scene): number {
  const fov = s.get('camera.fov_y_degrees') as number;
  return (2 * Math.tan(toRadians(fov) * 0.5)) / (s.get('image.height') as number);
}

/// The focus plane's distance (Scene::focus_distance).
export function focusDistance(s: Scene): number {
  const d = s.get('camera.focus_distance') as number;
  if (d > 0) return d;
  const eye = s.get('camera.eye') as V3;
  const target = s.get('camera.target') as V3;
  return length3(sub(target, eye));
}

const ALGEBRA_PARTS: Record<string, number> = { quaternion: 1, octonion: 2, sedenion: 4 };
const CODES: Record<string, string[]> = {
  normal_method: ['central', 'tetrahedral', 'analytic'],
  tracing: ['seed', 'cone'],
  colouring: ['flat', 'orbit_trap'],
};

/// A number of the algebra as 16 floats (hyper_from_f64: zeros past its dimension).
function hyper(v: number[]): number[] {
  return Array.from({ length: 16 }, (_, k) => v[k] ?? 0);
}

/// The environment map's frame in f64 (environment_frame of src/params.rs): up (`sky.up`,
/// unit), front (+z, or +y where |up.z| >= 0.9, made orthogonal to up) and the turn about up in
/// radians (`environment.rotation_degrees` modulo a full turn).
export function environmentFrame(s: Scene): { up: V3; front: V3; turn: number } {
  const up = unit(s.get('sky.up') as number[]) as V3;
  const axis: V3 = Math.abs(up[2]) < 0.9 ? [0, 0, 1] : [0, 1, 0];
  const along = dot(axis, up);
  const front = normalize([axis[0] - up[0] * along, axis[1] - up[1] * along, axis[2] - up[2] * along]);
  const tau = 2 * Math.PI;
  const r = toRadians(s.get('environment.rotation_degrees') as number) % tau;
  return { up, front, turn: r < 0 ? r + tau : r };
}

/// Every scene field of `struct Params` by name, in f64 (TraceParams::new); numbers, vectors,
/// or 16 floats for a number of the algebra. `envMap`: whether the scene's environment map is
/// loaded and bound (the page may not have its file yet).
export function traceParams(s: Scene, envMap: boolean): Map<string, number | number[]> {
  const frame = cameraFrame(s);
  const env = environmentFrame(s);
  const bounds = sliceBounds(s);
  const f = (k: string) => s.get(k) as number;
  const v = (k: string) => s.get(k) as number[];
  const b = (k: string) => ((s.get(k) as boolean) ? 1 : 0);
  const code = (field: string, key: string) => CODES[field].indexOf(s.get(key) as string);
  return new Map<string, number | number[]>([
    ['c', hyper(v('fractal.c'))],
    ['slice_x', hyper(v('slice.x'))],
    ['slice_y', hyper(v('slice.y'))],
    ['slice_z', hyper(v('slice.z'))],
    ['slice_offset', hyper(v('slice.offset'))],
    ['eye', v('camera.eye')],
    ['epsilon', f('fractal.epsilon')],
    ['cam_forward', frame.forward],
    ['tan_half_fov_y', frame.tanHalfFovY],
    ['cam_right', frame.right],
    ['aspect', f('image.width') / f('image.height')],
    ['cam_up', frame.up],
    ['escape_radius_squared', Math.min(f('fractal.escape_radius_squared'), ESCAPE_LIMIT_F32)],
    ['light', v('light.position')],
    ['bounds_radius_squared', bounds.radiusSquared],
    ['bounds_center', bounds.center],
    ['normal_tint', f('shading.normal_tint')],
    ['diffuse', v('shading.diffuse')],
    ['specular', f('shading.specular')],
    ['background', v('shading.background')],
    ['shininess', f('shading.shininess')],
    ['palette_phase', v('shading.palette_phase')],
    ['trap_scale', f('shading.trap_scale')],
    ['cut_normal', unit(v('cut.normal'))],
    ['cut_offset', f('cut.offset')],
    ['fog_colour', v('fog.colour')],
    ['fog_density', f('fog.density')],
    ['glow_colour', v('glow.colour')],
    ['glow_strength', f('glow.strength')],
    ['env_up', env.up],
    ['env_rotation', env.turn],
    ['env_front', env.front],
    ['env_intensity', f('environment.intensity')],
    ['shadow_factor', f('shading.shadow_factor')],
    ['normal_delta', f('shading.normal_delta')],
    ['step_scale', f('fractal.step_scale')],
    ['pixel_epsilon', f('fractal.pixel_epsilon')],
    ['pixel_angle', pixelAngle(s)],
    ['light_radius', f('light.radius')],
    ['ambient', f('shading.ambient')],
    ['occlusion', f('shading.occlusion')],
    ['trap_radius', f('shading.trap_radius')],
    ['aperture', f('camera.aperture')],
    ['focus_distance', focusDistance(s)],
    ['blade_rotation', toRadians(f('camera.blade_rotation'))],
    ['noise_target', f('path.noise_target')],
    ['fog_anisotropy', f('fog.anisotropy')],
    ['glow_radius', f('glow.radius')],
    ['max_iterations', f('fractal.max_iterations')],
    ['max_steps', f('fractal.max_steps')],
    ['width', f('image.width')],
    ['height', f('image.height')],
    ['shadows', b('shading.shadows')],
    ['normal_method', code('normal_method', 'shading.normal')],
    ['tracing', code('tracing', 'fractal.tracing')],
    ['algebra_parts', ALGEBRA_PARTS[s.get('fractal.algebra') as string]],
    ['samples', f('image.samples')],
    ['colouring', code('colouring', 'shading.colouring')],
    ['cut', b('cut.enabled')],
    ['blades', f('camera.blades')],
    ['min_samples', f('path.min_samples')],
    ['env_map', envMap ? 1 : 0],
    ['env_light', b('shading.environment_light')],
  ]);
}

/// Samples each dispatch adds to bands of `rows` rows of `width` pixels
/// (GpuTracer::samples_per_dispatch_in).
export function samplesPerDispatch(rows: number, width: number, samples: number): number {
  const bandPixels = rows * width;
  const fit = Math.min(Math.max(Math.floor(BAND_PIXELS / Math.max(bandPixels, 1)), 1), 2 ** 32 - 1);
  return Math.min(fit, MAX_SAMPLES_PER_DISPATCH, Math.max(samples, 1));
}

/// Samples one invocation of the path tracer traces in one dispatch: as many as keep samples x
/// rays x max_steps within 60,000 (each scattering event traces at most three rays, four with an
/// environment map), at least 1 and at most 8 (path_samples_per_dispatch of src/gpu/path.rs).
export function pathSamplesPerDispatch(bounces: number, maxSteps: number, environment: boolean): number {
  const rays = (3 + (environment ? 1 : 0)) * bounces + 1;
  return Math.min(Math.max(Math.floor(60_000 / (rays * Math.max(maxSteps, 1))), 1), 8);
}

/// The uniform of a dispatch over rows [rowOffset, rowOffset + rowCount) written from row
/// `outRow` on, `rowStride` pixels a row, adding the samples [start, end) (F::trace_uniform).
export interface Dispatch {
  rowOffset: number;
  rowCount: number;
  rowStride: number;
  outRow: number;
  sampleStart: number;
  sampleEnd: number;
}

/// The bytes of `struct Params` (f32) for `s` and one dispatch, `envMap` as traceParams.
export function packParams(
  s: Scene,
  d: Dispatch,
  envMap: boolean,
  layout: Layout = PARAMS_LAYOUT,
): Uint8Array<ArrayBuffer> {
  return packDispatch(layout, traceParams(s, envMap), d);
}

/// A uniform of a dispatch: its fields from `values`, the per-dispatch ones from `d` (a
/// uniform has those of them its layout names: the 2D view's has no samples).
function packDispatch(layout: Layout, values: Map<string, number | number[]>, d: Dispatch): Uint8Array<ArrayBuffer> {
  const perDispatch = new Map<string, number>([
    ['row_offset', d.rowOffset],
    ['row_count', d.rowCount],
    ['row_stride', d.rowStride],
    ['out_row', d.outRow],
    ['sample_start', d.sampleStart],
    ['sample_end', d.sampleEnd],
  ]);
  return pack(layout, (f) => (f.per_dispatch ? perDispatch : values).get(f.name));
}

/// The 2D view's `Julia2dParams` in f32 (Julia2dParams::new of src/params.rs), by name: c's
/// first two components as c = x + y i, the view's centre, half its width and height in the
/// complex plane.
export function julia2dParams(s: Scene): Map<string, number | number[]> {
  const c = s.get('fractal.c') as number[];
  const [w, h] = [s.get('image.width') as number, s.get('image.height') as number];
  const half = 0.5 * (s.get('view2d.extent') as number);
  return new Map<string, number | number[]>([
    ['c', [c[0], c[1]]],
    ['center', s.get('view2d.center') as number[]],
    ['half_extent', [half, (half * h) / w]],
    ['max_iterations', s.get('view2d.max_iterations') as number],
    ['width', w],
    ['height', h],
  ]);
}

/// The bytes of `struct Julia2dParams` for `s` and a band of rows (its per-dispatch fields:
/// row_offset, row_count, row_stride, out_row; `sampleStart` and `sampleEnd` unused).
export function packJulia2d(
  s: Scene,
  d: Dispatch,
  layout: Layout = JULIA2D_LAYOUT,
): Uint8Array<ArrayBuffer> {
  return packDispatch(layout, julia2dParams(s), d);
}

/// The path tracer's `PathParams` in f32 (PathParams::new, then GpuPathParams::new), by name.
export function pathParams(s: Scene): Map<string, number | number[]> {
  const f = (k: string) => s.get(k) as number;
  const v = (k: string) => s.get(k) as number[];
  const sun = f('sun.intensity');
  const light = f('light.intensity');
  return new Map<string, number | number[]>([
    ['sky_zenith', v('sky.zenith')],
    ['sky_intensity', f('sky.intensity')],
    ['sky_horizon', v('sky.horizon')],
    ['bounces', f('path.bounces')],
    ['sky_ground', v('sky.ground')],
    ['roulette_start', ROULETTE_START],
    ['sky_up', unit(v('sky.up'))],
    ['clamp_contribution', f('path.clamp')],
    ['sun_direction', unit(v('sun.direction'))],
    ['sun_one_minus_cos', sunOneMinusCos(f('sun.angular_radius_degrees'))],
    ['sun_irradiance', v('sun.colour').map((c) => c * sun)],
    ['sampler', SAMPLER_CODES[s.get('path.sampler') as string]],
    ['light_intensity', [light, light, light]],
    ['strategy', 0],
    ['roughness', f('material.roughness')],
    ['metallic', f('material.metallic')],
    ['specular', f('material.specular')],
    ['multiscatter', s.get('material.multiscatter') ? 1 : 0],
    ['regularize', f('path.regularize')],
    ['seed', f('path.seed')],
    ['step_scale', f('path.step_scale')],
    ['pad1', 0],
    ['emission', v('material.emission')],
    ['pad2', 0],
  ]);
}

/// The least 1 - cos(angular radius) a sun is given (SUN_MIN_ONE_MINUS_COS of src/cpu/light.rs).
const SUN_MIN_ONE_MINUS_COS = 1e-30;

/// A sun's 1 - cos(angular radius), as 2 sin^2(theta / 2) in f64 (sun_one_minus_cos of
/// src/cpu/light.rs): no cancellation where the cosine is near 1.
export function sunOneMinusCos(degrees: number): number {
  const half = 0.5 * toRadians(degrees);
  return Math.max(2.0 * Math.sin(half) * Math.sin(half), SUN_MIN_ONE_MINUS_COS);
}

/// Russian roulette's first scattering event (ROULETTE_START of src/cpu/path/uniform.rs).
export const ROULETTE_START = 3;
/// The shader's `sampler` numbers (SAMPLER_SOBOL, SAMPLER_RANDOM of src/cpu/sobol.rs).
const SAMPLER_CODES: Record<string, number> = { sobol: 0, random: 1 };

/// The bytes of `struct PathParams` for `s`.
export function packPath(s: Scene, layout: Layout = PATH_LAYOUT): Uint8Array<ArrayBuffer> {
  const values = pathParams(s);
  return pack(layout, (f) => values.get(f.name));
}

/// A uniform's bytes by its layout, each field's value(s) from `value` (u32 as they are, f32
/// rounded from f64).
function pack(
  layout: Layout,
  valueOf: (f: FieldLayout) => number | number[] | undefined,
): Uint8Array<ArrayBuffer> {
  const bytes = new Uint8Array(layout.size);
  const view = new DataView(bytes.buffer);
  for (const field of layout.fields) {
    const value = valueOf(field);
    if (value === undefined) throw new Error(`no value for ${layout.name}'s ${field.name}`);
    const items = Array.isArray(value) ? value : [value];
    const scalar = field.type === 'u32' ? 'u32' : 'f32';
    const count = field.size / 4;
    if (items.length < count) throw new Error(`${field.name}: ${items.length} of ${count} values`);
    for (let k = 0; k < count; k++) {
      const at = field.offset + 4 * k;
      if (scalar === 'u32') view.setUint32(at, items[k], true);
      else view.setFloat32(at, Math.fround(items[k]), true);
    }
  }
  return bytes;
}

/// The scene's first dispatch over the whole image as one band, as `gpu-params` prints it.
export function firstDispatch(s: Scene): Dispatch {
  const width = s.get('image.width') as number;
  const height = s.get('image.height') as number;
  const samples = s.get('image.samples') as number;
  return {
    rowOffset: 0,
    rowCount: height,
    rowStride: width,
    outRow: 0,
    sampleStart: 0,
    sampleEnd: samplesPerDispatch(height, width, samples),
  };
}

/// The f32 value the GPU reads of an f64 (what a uniform field holds).
const f32 = Math.fround;

/// The shaded picture's pipeline override constants for `s` (Variant::of(params, true), or in
/// path mode Variant::of_path: none of phong's shading, no cone), as `gpu-params` prints them,
/// in order; `envMap` as traceParams.
export function overrides(s: Scene, envMap: boolean): [string, number][] {
  const p = traceParams(s, envMap);
  const path = s.get('shading.model') === 'path';
  const n = (k: string) => p.get(k) as number;
  const standard = (k: string, axis: number) =>
    (p.get(k) as number[]).every((x, i) => f32(x) === (i === axis ? 1 : 0));
  const b = (v: boolean) => (v ? 1 : 0);
  const samples = n('samples') > 1;
  return [
    ['SHADOWS', path ? 0 : n('shadows')],
    ['NORMAL_METHOD', n('normal_method')],
    ['STANDARD_SLICE', b(standard('slice_x', 0) && standard('slice_y', 1) && standard('slice_z', 2))],
    ['OVER_RELAXED', b(f32(n('step_scale')) > 1)],
    ['PIXEL_EPSILON', b(f32(n('pixel_epsilon')) > 0)],
    ['SHADE', 1],
    ['CONE_TRACING', b(!path && n('tracing') === 1)],
    ['ALGEBRA_PARTS', n('algebra_parts')],
    ['SAMPLES', b(samples)],
    ['SOFT_SHADOWS', b(!path && n('shadows') === 1 && f32(n('light_radius')) > 0)],
    ['OCCLUSION', b(!path && f32(n('occlusion')) > 0)],
    ['ORBIT_TRAP', b(n('colouring') === 1)],
    ['CUT', n('cut')],
    ['LENS', b(f32(n('aperture')) > 0)],
    ['ADAPTIVE', b(samples && f32(n('noise_target')) > 0)],
    ['FOG', b(f32(n('fog_density')) > 0)],
    ['GLOW', b(!path && f32(n('glow_strength')) > 0)],
    ['ENVIRONMENT', n('env_map')],
  ];
}

/// Bytes as lowercase hex, two digits a byte.
export function hex(bytes: Uint8Array): string {
  return Array.from(bytes, (x) => x.toString(16).padStart(2, '0')).join('');
}
