// The work views (`image.view = "steps"`, `"divergence"`, `"samples"`): the TypeScript twin of
// src/heatmap.rs's colour map, logarithmic scale, legend values and views, and of
// src/stats.rs's 8x8 block divergence. The legend strip's drawing (its text) is the page's
// own; its numbers are these.

/// Viridis as nine stops from 0 to 1, linearly interpolated (COLOUR_STOPS).
export const COLOUR_STOPS: [number, number, number][] = [
  [68, 1, 84],
  [71, 45, 123],
  [59, 82, 139],
  [44, 114, 142],
  [33, 145, 140],
  [40, 174, 128],
  [94, 201, 98],
  [173, 220, 48],
  [253, 231, 37],
];

/// Rust's f64::round: half away from zero (JavaScript's Math.round goes half up).
function roundHalfAway(x: number): number {
  return x < 0 ? -Math.round(-x) : Math.round(x);
}

/// The colour map at t in [0, 1] (clamped; NaN counts as 0).
export function colourMap(t: number): [number, number, number] {
  const u = Number.isNaN(t) ? 0 : Math.min(Math.max(t, 0), 1);
  const x = u * (COLOUR_STOPS.length - 1);
  const k = Math.min(Math.floor(x), COLOUR_STOPS.length - 2);
  const f = x - k;
  const [a, b] = [COLOUR_STOPS[k], COLOUR_STOPS[k + 1]];
  return [0, 1, 2].map((c) => roundHalfAway(a[c] + (b[c] - a[c]) * f)) as [number, number, number];
}

/// Where v lies on the bar from min to max: ln(1 + v - min) / ln(1 + max - min); 0 when
/// min = max.
export function scale(v: number, min: number, max: number): number {
  if (max <= min) return 0;
  return Math.log1p(Math.max(v - min, 0)) / Math.log1p(max - min);
}

export interface Legend {
  min: number;
  mid: number;
  max: number;
  title: string;
}

export interface HeatMap {
  width: number;
  height: number;
  rgb: Uint8Array;
  legend: Legend;
}

function legend(min: number, max: number, title: string): Legend {
  // scale(mid) = 1/2: 1 + mid - min = sqrt(1 + max - min).
  const mid = min + roundHalfAway(Math.sqrt(1 + (max - min)) - 1);
  return { min, mid, max, title };
}

/// Values mapped from their smallest to their largest (over the pixels shown); black elsewhere.
function heatMap(
  values: ArrayLike<number>,
  width: number,
  height: number,
  title: string,
  shown: (k: number) => boolean,
): HeatMap {
  let [min, max] = [Infinity, 0];
  for (let k = 0; k < values.length; k++) {
    if (shown(k)) {
      min = Math.min(min, values[k]);
      max = Math.max(max, values[k]);
    }
  }
  if (min > max) [min, max] = [0, 0];
  const rgb = new Uint8Array(values.length * 3);
  for (let k = 0; k < values.length; k++) {
    if (shown(k)) rgb.set(colourMap(scale(values[k], min, max)), 3 * k);
  }
  return { width, height, rgb, legend: legend(min, max, title) };
}

/// Pixels a side of the divergence blocks (DIVERGENCE_BLOCK: the tracer's workgroup).
export const DIVERGENCE_BLOCK = 8;

function blockOf(k: number, width: number): number {
  const columns = Math.ceil(width / DIVERGENCE_BLOCK);
  const [i, j] = [k % width, Math.floor(k / width)];
  return Math.floor(j / DIVERGENCE_BLOCK) * columns + Math.floor(i / DIVERGENCE_BLOCK);
}

/// The most steps of each 8x8 block (stats::block_maxima).
export function blockMaxima(steps: ArrayLike<number>, width: number, height: number): number[] {
  const columns = Math.ceil(width / DIVERGENCE_BLOCK);
  const max = new Array<number>(columns * Math.ceil(height / DIVERGENCE_BLOCK)).fill(0);
  for (let k = 0; k < steps.length; k++) {
    const b = blockOf(k, width);
    max[b] = Math.max(max[b], steps[k]);
  }
  return max;
}

/// The `steps` view: steps per primary ray, black where the ray misses the ball (0 steps).
export function stepsView(steps: ArrayLike<number>, width: number, height: number): HeatMap {
  return heatMap(steps, width, height, 'steps per ray (log scale)', (k) => steps[k] > 0);
}

/// The `divergence` view: each pixel's block's most steps minus its own, black where the whole
/// block does no work.
export function divergenceView(steps: ArrayLike<number>, width: number, height: number): HeatMap {
  const blockMax = blockMaxima(steps, width, height);
  const wasted = Array.from(steps, (s, k) => blockMax[blockOf(k, width)] - s);
  const title = 'wasted steps per pixel, 8x8 tiles (log scale)';
  return heatMap(wasted, width, height, title, (k) => blockMax[blockOf(k, width)] > 0);
}

/// The `samples` view: the samples each pixel took (adaptive sampling), every pixel shown.
export function samplesView(samples: ArrayLike<number>, width: number, height: number): HeatMap {
  return heatMap(samples, width, height, 'samples per pixel (log scale)', () => true);
}
