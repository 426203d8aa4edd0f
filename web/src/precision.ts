// What f32 cannot resolve in a scene's 3D slice: the TypeScript twin of
// `precision::slice_warnings` (src/precision.rs) in f32, the page's only precision (WebGPU has
// no f64). The page stops zooming where these say so, and shows the line.

import type { Scene } from './scene';
import { type V3, length3, sub, toRadians } from './vector';

/// f32's relative spacing of values, with margin: 8 f32::EPSILON (Real::RELATIVE_EPSILON).
export const F32_RELATIVE_SPACING = 8 * 2 ** -23;
/// |z|^2 beyond which f32 iterations overflow (Real::ESCAPE_LIMIT).
export const F32_ESCAPE_LIMIT = 1e8;
const REMEDY = 'use --precision f64 (or auto)';

/// Rust's `{:e}`: the shortest digits, as `1e-9`, `1.5e-5`, `3e0`.
export function rustExp(x: number): string {
  return x.toExponential().replace('e+', 'e');
}

/// Rust's `{:.1e}`: one decimal, as `2.9e-6`, `3.0e0`.
export function rustExp1(x: number): string {
  return x.toExponential(1).replace('e+', 'e');
}


/// Each warning's line, in order: epsilon below the spacing of f32 values at the rays' reach,
/// a pixel's footprint at the target below it, an escape radius f32 iterations would overflow.
export function sliceWarnings(s: Scene): string[] {
  const eye = s.get('camera.eye') as V3;
  const target = s.get('camera.target') as V3;
  const bounding = s.get('fractal.bounding_radius_squared') as number;
  const reach = Math.max(Math.max(length3(eye), Math.sqrt(bounding)), 1);
  const spacing = reach * F32_RELATIVE_SPACING;
  const out: string[] = [];
  const epsilon = s.get('fractal.epsilon') as number;
  if (epsilon < spacing) {
    out.push(
      `fractal.epsilon = ${rustExp(epsilon)} is below the spacing of f32 values at distance ` +
        `${reach.toFixed(3)} (${rustExp1(spacing)}): hits are taken there instead; ${REMEDY}`,
    );
  }
  const view = length3(sub(target, eye));
  const fov = s.get('camera.fov_y_degrees') as number;
  const footprint =
    (2 * view * Math.tan(toRadians(fov) * 0.5)) / (s.get('image.height') as number);
  if (footprint < spacing) {
    out.push(
      `a pixel spans ${rustExp1(footprint)} at the target, below the spacing of f32 values ` +
        `(${rustExp1(spacing)}): neighbouring pixels trace the same points; ${REMEDY}`,
    );
  }
  const escape = s.get('fractal.escape_radius_squared') as number;
  if (escape > F32_ESCAPE_LIMIT) {
    out.push(
      `fractal.escape_radius_squared = ${rustExp(escape)} would overflow f32 iterations: ` +
        `${rustExp(F32_ESCAPE_LIMIT)} is used; ${REMEDY}`,
    );
  }
  return out;
}

/// Whether f32 still resolves the view: no warning at all (the page's zoom stops before this
/// turns false).
export function f32Resolves(s: Scene): boolean {
  return sliceWarnings(s).length === 0;
}

/// The 2D view's f32 warnings (julia2d_warnings): a pixel (extent / width) below the spacing of
/// f32 values at the view's farthest point from 0 (|centre| + half the extent, at least 1).
export function julia2dWarnings(s: Scene): string[] {
  const [x, y] = s.get('view2d.center') as number[];
  const extent = s.get('view2d.extent') as number;
  const reach = Math.max(Math.max(Math.abs(x), Math.abs(y)) + 0.5 * extent, 1);
  const spacing = reach * F32_RELATIVE_SPACING;
  const pixel = extent / (s.get('image.width') as number);
  if (!(pixel < spacing)) return [];
  return [
    `a pixel spans ${rustExp1(pixel)} (view2d.extent / image.width), below the spacing of f32 ` +
      `values (${rustExp1(spacing)}): neighbouring pixels iterate the same points; use --precision f64`,
  ];
}
