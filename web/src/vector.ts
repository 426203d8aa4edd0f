// The few vector operations the host's twins need, each as the Rust host computes it (the
// order of its additions, glam's normalize), so that the f64 values agree bit for bit.

export type V3 = [number, number, number];

/// The Euclidean inner product of two vectors of equal length (src/scene/mod.rs's `dot`).
export function dot(a: number[], b: number[]): number {
  let sum = 0;
  for (let k = 0; k < a.length; k++) sum += a[k] * b[k];
  return sum;
}

export function sub(a: V3, b: V3): V3 {
  return [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
}

/// glam's length: sqrt(x x + y y + z z).
export function length3(a: V3): number {
  return Math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

/// glam's cross product.
export function cross(a: V3, b: V3): V3 {
  return [a[1] * b[2] - b[1] * a[2], a[2] * b[0] - b[2] * a[0], a[0] * b[1] - b[0] * a[1]];
}

/// glam's normalize: times the reciprocal of the length.
export function normalize(a: V3): V3 {
  const r = 1 / length3(a);
  return [a[0] * r, a[1] * r, a[2] * r];
}

/// Rust's f64::to_radians.
export function toRadians(degrees: number): number {
  return degrees * (Math.PI / 180);
}
