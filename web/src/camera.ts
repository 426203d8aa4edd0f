// The explorer's camera controller: the TypeScript twin of src/explore/camera.rs (orbit about
// the target, zoom toward it, pan across the view; the 2D view's pan and zoom; and the pointer's
// moves as camera moves), in f64 with the Rust side's operations in its order (glam's quaternion
// rotation, normalize, cross), so that a drag in the page leaves the camera bit for bit where
// the desktop explorer leaves it (test/camera.test.ts replays test/fixtures/camera.json).
// `up` never changes; the eye never reaches the target or lines up with `up`.

import type { Scene } from './scene';
import { type V3, cross, dot, length3, normalize, sub, toRadians } from './vector';

/// Radians of orbit per point dragged, and zoom per point scrolled (the wheel's points).
export const ORBIT_PER_POINT = 0.01;
export const ZOOM_PER_POINT = 0.002;
/// Closest the eye may come to the target, and farthest it may go.
export const MIN_DISTANCE = 1e-3;
export const MAX_DISTANCE = 1e3;
/// Closest the view direction may come to `up` (or to -up), in radians.
const MIN_POLAR = 0.01;
/// The field of view a zoom out widens back to before the eye moves away again.
export const WIDE_FOV_DEGREES = 45.0;
/// The narrowest field of view a zoom reaches.
export const MIN_FOV_DEGREES = 1e-10;
/// The narrowest 2D extent the mouse zooms to.
export const MIN_EXTENT = 1e-12;

export interface Camera {
  eye: V3;
  target: V3;
  up: V3;
  fovYDegrees: number;
}

export interface View2d {
  center: [number, number];
  extent: number;
}

/// The scene's camera.
export function cameraOf(s: Scene): Camera {
  return {
    eye: [...(s.get('camera.eye') as number[])] as V3,
    target: [...(s.get('camera.target') as number[])] as V3,
    up: [...(s.get('camera.up') as number[])] as V3,
    fovYDegrees: s.get('camera.fov_y_degrees') as number,
  };
}

/// Writes `cam` into the scene.
export function setCamera(s: Scene, cam: Camera): void {
  s.set('camera.eye', [...cam.eye]);
  s.set('camera.target', [...cam.target]);
  s.set('camera.up', [...cam.up]);
  s.set('camera.fov_y_degrees', cam.fovYDegrees);
}

export function view2dOf(s: Scene): View2d {
  const c = s.get('view2d.center') as number[];
  return { center: [c[0], c[1]], extent: s.get('view2d.extent') as number };
}

export function setView2d(s: Scene, v: View2d): void {
  s.set('view2d.center', [...v.center]);
  s.set('view2d.extent', v.extent);
}

const add = (a: V3, b: V3): V3 => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scaled = (a: V3, k: number): V3 => [a[0] * k, a[1] * k, a[2] * k];

/// glam's DQuat::from_axis_angle then `* v` (mul_vec3): the rotation of `v` by `angle` about
/// the unit `axis`.
function rotate(axis: V3, angle: number, v: V3): V3 {
  const s = Math.sin(angle * 0.5);
  const w = Math.cos(angle * 0.5);
  const b = scaled(axis, s);
  const b2 = dot(b, b);
  return add(add(scaled(v, w * w - b2), scaled(b, dot(v, b) * 2.0)), scaled(cross(b, v), w * 2.0));
}

/// glam's normalize_or_zero.
function normalizeOrZero(a: V3): V3 {
  const r = 1 / length3(a);
  return Number.isFinite(r) && r > 0 ? scaled(a, r) : [0, 0, 0];
}

const clamp = (x: number, lo: number, hi: number) => Math.min(Math.max(x, lo), hi);
const tanHalf = (deg: number) => Math.tan(toRadians(deg) * 0.5);
/// Rust's f64::to_degrees.
const toDegrees = (radians: number) => radians * (180 / Math.PI);

/// Turns the eye about the target: `azimuth` about `up`, `elevation` toward `up` (radians).
export function orbit(cam: Camera, azimuth: number, elevation: number): void {
  const [eye, target, up] = [cam.eye, cam.target, normalize(cam.up)];
  let offset = rotate(up, azimuth, sub(eye, target));
  // Angle between offset and up, kept inside (MIN_POLAR, pi - MIN_POLAR).
  const polar = Math.acos(clamp(dot(normalize(offset), up), -1, 1));
  const newPolar = clamp(polar - elevation, MIN_POLAR, Math.PI - MIN_POLAR);
  const axis = normalizeOrZero(cross(up, offset));
  if (!(axis[0] === 0 && axis[1] === 0 && axis[2] === 0)) {
    offset = rotate(axis, newPolar - polar, offset);
  }
  cam.eye = add(target, offset);
}

/// Zooms by `factor` (< 1: in, > 1: out): the eye moves toward or away from the target, and
/// once it is as close as it may come the field of view narrows instead; zooming out widens the
/// field of view back to WIDE_FOV_DEGREES first, then moves the eye away.
export function zoom(cam: Camera, factor: number): void {
  const offset = sub(cam.eye, cam.target);
  const atFloor = length3(offset) <= MIN_DISTANCE * (1.0 + 1e-9);
  if (factor > 1.0 && atFloor && cam.fovYDegrees < WIDE_FOV_DEGREES) {
    // Out: the footprint (with tan(fov / 2)) grows by the factor, up to the wide view; the
    // rest of the factor moves the eye.
    const [now, wide] = [tanHalf(cam.fovYDegrees), tanHalf(WIDE_FOV_DEGREES)];
    const widened = Math.min(now * factor, wide);
    cam.fovYDegrees = toDegrees(2.0 * Math.atan(widened));
    factor *= now / widened;
  }
  const wanted = length3(offset) * factor;
  const distance = clamp(wanted, MIN_DISTANCE, MAX_DISTANCE);
  cam.eye = add(cam.target, scaled(normalize(offset), distance));
  if (wanted < MIN_DISTANCE) {
    // In, past the closest the eye comes: the rest narrows the view.
    const narrowed = (tanHalf(cam.fovYDegrees) * wanted) / MIN_DISTANCE;
    cam.fovYDegrees = Math.max(toDegrees(2.0 * Math.atan(narrowed)), MIN_FOV_DEGREES);
  }
}

/// How much slower the camera orbits at this field of view than at WIDE_FOV_DEGREES.
export function orbitScale(cam: Camera): number {
  return Math.min(tanHalf(cam.fovYDegrees) / tanHalf(WIDE_FOV_DEGREES), 1.0);
}

/// Slides eye and target together across the view: `right` and `up` in units of the view's
/// height at the target's distance.
export function pan(cam: Camera, right: number, up: number): void {
  const [eye, target] = [cam.eye, cam.target];
  const forward = normalize(sub(target, eye));
  const r = normalize(cross(forward, cam.up));
  const u = cross(r, forward);
  const height = 2.0 * Math.tan(toRadians(cam.fovYDegrees) * 0.5) * length3(sub(target, eye));
  const shift = scaled(add(scaled(r, right), scaled(u, up)), height);
  cam.eye = add(eye, shift);
  cam.target = add(target, shift);
}

/// A drag of (dx, dy) points with the orbiting button.
export function dragOrbit(cam: Camera, dx: number, dy: number): void {
  const rate = ORBIT_PER_POINT * orbitScale(cam);
  orbit(cam, dx * rate, dy * rate);
}

/// A drag of (dx, dy) points with the panning button across a view `height` points high.
export function dragPan(cam: Camera, dx: number, dy: number, height: number): void {
  const h = Math.max(height, 1.0);
  pan(cam, -dx / h, dy / h);
}

/// The wheel turned by `scroll` points (positive: zooming in).
export function wheelZoom(cam: Camera, scroll: number): void {
  zoom(cam, Math.exp(-scroll * ZOOM_PER_POINT));
}

/// The 2D view's extent between MIN_EXTENT and its slider's widest (`widest`).
export function clampExtent(extent: number, widest: number): number {
  return clamp(extent, MIN_EXTENT, widest);
}

/// A drag of (dx, dy) points across the 2D view, `width` points wide.
export function drag2d(v: View2d, dx: number, dy: number, width: number): void {
  const perPoint = v.extent / Math.max(width, 1.0);
  v.center[0] -= dx * perPoint;
  v.center[1] += dy * perPoint;
}

/// The wheel turned by `scroll` points over the 2D view, `width` points wide, with the pointer
/// `fromCentre` points right of and below the view's centre (if over it): the point under the
/// pointer stays there. `widest` is view2d.extent's slider's maximum.
export function wheelZoom2d(
  v: View2d,
  scroll: number,
  width: number,
  fromCentre: [number, number] | null,
  widest: number,
): void {
  const perPoint = v.extent / Math.max(width, 1.0);
  const extent = clampExtent(v.extent * Math.exp(-scroll * ZOOM_PER_POINT), widest);
  const factor = extent / v.extent;
  if (fromCentre !== null) {
    const under = [v.center[0] + fromCentre[0] * perPoint, v.center[1] - fromCentre[1] * perPoint];
    for (let k = 0; k < 2; k++) v.center[k] = under[k] - (under[k] - v.center[k]) * factor;
  }
  v.extent = extent;
}
