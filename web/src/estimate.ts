// The image's error on request in the page: the twin of src/estimate.rs's raw estimate
// (HalvesSums: each pixel's two halves, the means of its two streams, give (a - b)^2 / 4 a
// channel) and of src/render/target.rs's pass schedule (next_samples) for `image.target_error`.
// test/estimate.test.ts holds both to the library's numbers (test/fixtures/estimate.json), bit
// for bit: the sums run in the library's order, in f64, which a JS number is.

/// An image's estimated error: the root of its estimated mean squared error over every channel
/// and pixel of the linear image, and that over the image's mean.
export interface ErrorEstimate {
  rmse: number;
  relative: number;
}

/// Rust's f64::MIN_POSITIVE (the smallest normal f64; Number.MIN_VALUE is the smallest
/// subnormal).
const F64_MIN_POSITIVE = 2.2250738585072014e-308;

/// The raw estimate of a path-traced image of `width` pixels a row from the accumulator's first
/// three planes, one after another, four f32s a pixel each (accumulate.wgsl's `accumulated`): the
/// mean colour the pixel shows, then its halves A and B (a half's mean colour and the samples in
/// it). Null where no pixel's halves both hold a sample.
export function rawEstimate(planes: Float32Array, width: number): ErrorEstimate | null {
  const pixels = Math.floor(planes.length / 12);
  const cut = Math.max(width, 1);
  let [squared, estimated, sum] = [0, 0, 0];
  // Row by row, each row's pixels in order and the rows added in order: the library's order.
  for (let row = 0; row * cut < pixels; row++) {
    let [rowSquared, rowEstimated, rowSum] = [0, 0, 0];
    for (let k = row * cut; k < Math.min((row + 1) * cut, pixels); k++) {
      const m = 4 * k;
      const total = planes[m] + planes[m + 1] + planes[m + 2];
      const v = halfVariance(planes, 4 * (pixels + k), 4 * (2 * pixels + k));
      if (v !== null) {
        rowSquared = rowSquared + (v[0] + v[1] + v[2]);
        rowEstimated += 3;
      }
      rowSum = rowSum + total;
    }
    squared += rowSquared;
    estimated += rowEstimated;
    sum += rowSum;
  }
  if (estimated === 0) return null;
  const rmse = Math.sqrt(squared / estimated);
  const mean = sum / Math.max(3 * pixels, 1);
  return { rmse, relative: rmse / Math.max(Math.abs(mean), F64_MIN_POSITIVE) };
}

/// A pixel's estimated variance of its mean, channel by channel, from its halves at `a` and
/// `b` in `planes`: (a - b)^2 / 4; null where a half holds no sample (src/estimate.rs's
/// half_colour and half_variance).
function halfVariance(planes: Float32Array, a: number, b: number): [number, number, number] | null {
  if (planes[a + 3] === 0 || planes[b + 3] === 0) return null;
  const v: [number, number, number] = [0, 0, 0];
  for (let c = 0; c < 3; c++) {
    const d = planes[a + c] - planes[b + c];
    v[c] = (d * d) / 4;
    if (!Number.isFinite(v[c])) return null;
  }
  return v;
}

/// The first pass's samples under `image.target_error` (or `image.samples`, where fewer).
export const FIRST_PASS = 16;
/// The margin a later pass's samples are multiplied by.
export const MARGIN = 1.2;
/// The least growth from one pass to the next.
export const LEAST_GROWTH = 1.5;

/// The samples of the pass after one of `samples` whose relative estimate was `estimate`, to
/// reach `target` with at most `most`: `min(most, even(ceil(max(1.2 n (e / E)^2, 1.5 n))))`;
/// `most` without an estimate (docs/CONTRACT.md's schedule).
export function nextSamples(samples: number, estimate: number | null, target: number, most: number): number {
  if (estimate === null) return most;
  // Rust's powi(2) is one multiplication.
  const ratio = estimate / target;
  const asked = samples * (ratio * ratio) * MARGIN;
  const n = Math.min(Math.ceil(Math.max(asked, samples * LEAST_GROWTH)), most);
  return Math.min(n + (n % 2), most);
}

/// The keyword of the tEXt chunk in which a PNG records its estimated error (ERROR_PNG_KEYWORD
/// of src/output.rs).
export const ERROR_PNG_KEYWORD = 'qjulia-error';

/// `x` as Rust's Display writes an f64: the shortest digits that read back as `x` (as
/// JavaScript's), but never in exponent notation, and no `.0` on a whole number.
export function rustFloat(x: number): string {
  if (!Number.isFinite(x)) return Number.isNaN(x) ? 'NaN' : x > 0 ? 'inf' : '-inf';
  if (x === 0) return Object.is(x, -0) ? '-0' : '0';
  const sign = x < 0 ? '-' : '';
  const [mantissa, power] = Math.abs(x).toExponential().split('e');
  const digits = mantissa.replace('.', '');
  const e = Number(power);
  if (e >= digits.length - 1) return sign + digits + '0'.repeat(e - digits.length + 1);
  if (e >= 0) return `${sign}${digits.slice(0, e + 1)}.${digits.slice(e + 1)}`;
  return `${sign}0.${'0'.repeat(-e - 1)}${digits}`;
}

/// What a PNG records of an estimate (src/output.rs's error_text_of): TOML of
/// `estimated_rmse` and `estimated_relative_rmse`, and with `image.target_error` what stopped
/// the render and its last pass's samples.
export function errorText(rmse: number, relative: number, target: { stopped_by: string; samples: number } | null): string {
  let text = `estimated_rmse = ${rustFloat(rmse)}\nestimated_relative_rmse = ${rustFloat(relative)}\n`;
  if (target !== null) text += `stopped_by = "${target.stopped_by}"\nsamples = ${target.samples}\n`;
  return text;
}
