// The WGSL kernels the page runs, composed at load from the project's shaders/ (bundled at build
// time) as shaders/kernels.json declares them, by the composer's twin (src/compose.ts): the
// kernels the declaration marks `web`, each in f32 (WebGPU has no f64).

import declaration from '../../shaders/kernels.json';
import { compose } from './compose';

/// Every file of shaders/ by its stem.
export const FILES: Record<string, string> = Object.fromEntries(
  Object.entries(
    import.meta.glob('../../shaders/*.wgsl', { query: '?raw', import: 'default', eager: true }) as Record<
      string,
      string
    >,
  ).map(([path, text]) => [path.replace(/^.*\//, '').replace(/\.wgsl$/, ''), text]),
);

/// The declared features' names.
export const FEATURES: readonly string[] = declaration.features.map((f) => f.name);

/// The kernel declared as `name`, composed.
export function kernel(name: string): string {
  const k = declaration.kernels.find((d) => d.name === name);
  if (k === undefined) throw new Error(`no kernel ${name} in shaders/kernels.json`);
  return compose((n) => FILES[n], FEATURES, k.root, k.features).text;
}

/// The tracer in f32.
export const TRACE_MODULE = kernel('trace');
/// The path tracer in f32.
export const PATH_MODULE = kernel('path');
/// The 2D Julia view in f32.
export const JULIA2D_MODULE = kernel('julia2d');
