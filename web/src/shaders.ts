// The WGSL kernels the page runs, composed from the project's shaders/ (bundled at build time) as
// shaders/kernels.json declares them, by the composer's twin (src/compose.ts): the kernels the
// declaration marks `web`, each in f32 (WebGPU has no f64), composed for each scene's variant
// (the scene features its override constants leave on: splitConstants, the twin of
// src/gpu/shaders.rs's split_constants).

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

interface SceneFeature {
  name: string;
  constant: string;
  on: number[];
}

/// Each scene feature, its constant and the values that turn it on (shaders/kernels.json's
/// defaults: its own name, [1]).
const SCENE: readonly SceneFeature[] = declaration.features
  .filter((f) => 'scene' in f && f.scene === true)
  .map((f) => ({
    name: f.name,
    constant: 'constant' in f && typeof f.constant === 'string' ? f.constant : f.name,
    on: 'on' in f && Array.isArray(f.on) ? (f.on as number[]) : [1],
  }));

/// The features the scene decides (marked `scene`), in the declaration's order.
export const SCENE_FEATURES: readonly string[] = SCENE.map((f) => f.name);

/// A pipeline's override constants split into the scene features the text is composed with and
/// the constants left for the pipeline (src/gpu/shaders.rs's split_constants): a scene feature
/// is on where the constants hold its constant with one of its values, off where they hold it
/// with another, on where they do not hold it; the scene features' constants are not passed on
/// (the text has no such override). Without a variant every scene feature is on: the generic
/// kernel.
export function splitConstants(constants: readonly [string, number][]): {
  on: string[];
  left: [string, number][];
} {
  const on = SCENE.filter((f) => {
    const held = constants.find(([n]) => n === f.constant);
    return held === undefined || f.on.includes(held[1]);
  });
  const consumed = SCENE.map((f) => f.constant);
  return {
    on: on.map((f) => f.name),
    left: constants.filter(([n]) => !consumed.includes(n)),
  };
}

/// The kernel declared as `name`, composed with its features and the scene features `scene`
/// (all of them unless given).
export function kernel(name: string, scene: readonly string[] = SCENE_FEATURES): string {
  const k = declaration.kernels.find((d) => d.name === name);
  if (k === undefined) throw new Error(`no kernel ${name} in shaders/kernels.json`);
  return compose((n) => FILES[n], FEATURES, k.root, [...k.features, ...scene]).text;
}

/// The tracer in f32, generic.
export const TRACE_MODULE = kernel('trace');
/// The path tracer in f32, generic.
export const PATH_MODULE = kernel('path');
/// The 2D Julia view in f32.
export const JULIA2D_MODULE = kernel('julia2d');
