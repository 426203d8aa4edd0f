// The display transform of path mode: linear radiance to the 8-bit sRGB a PNG holds, the twin
// of src/display.rs (per channel, in f64: exposure `x 2^exposure`, the tone map, the sRGB
// transfer function, then `floor(255 v + 0.5)`). test/display.test.ts holds it to the
// library's bytes (test/fixtures/display.json). Phong mode keeps the seed's clamp, mean and
// round, which the kernel does, and does not come here.

/// The curve at `x` (exposure applied), in [0, 1]; NaN and negative values give 0.
export function toneMap(name: string, x: number): number {
  // Rust's f64::max returns the other operand for a NaN: a NaN becomes 0.
  const v = Number.isNaN(x) ? 0 : Math.max(x, 0);
  const y = name === 'reinhard' ? reinhard(v) : name === 'aces' ? acesNarkowicz(v) : v;
  return Math.min(Math.max(y, 0), 1);
}

/// Reinhard's simple operator, `x / (1 + x)`.
export function reinhard(x: number): number {
  return x / (1.0 + x);
}

/// Narkowicz's 2015 ACES fit, `x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)`, unclamped.
export function acesNarkowicz(x: number): number {
  return (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
}

/// The sRGB transfer function (IEC 61966-2-1) of `v` in [0, 1].
export function srgbEncode(v: number): number {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * v ** (1.0 / 2.4) - 0.055;
}

/// `v` in [0, 1] rounded to 8 bits: `floor(255 v + 0.5)`.
export function quantise(v: number): number {
  return Math.floor(255.0 * Math.min(Math.max(v, 0), 1) + 0.5);
}

/// A scene's display transform (`image.exposure`, `image.tone_map`).
export class Display {
  private scale: number;

  constructor(
    public exposure: number,
    public tone: string,
  ) {
    this.scale = 2 ** exposure;
  }

  /// One channel of linear radiance (an f32) as its 8-bit sRGB value.
  encode(linear: number): number {
    return quantise(srgbEncode(toneMap(this.tone, linear * this.scale)));
  }

  /// The packed colours (0xFFBBGGRR) of the accumulator's vec4 per pixel (RGB the linear
  /// mean; the fourth float is adaptive sampling's state).
  packAll(accumulated: Float32Array): Uint32Array {
    const out = new Uint32Array(accumulated.length / 4);
    for (let p = 0; p < out.length; p++) {
      const [r, g, b] = [0, 1, 2].map((c) => this.encode(accumulated[4 * p + c]));
      out[p] = (0xff000000 | (b << 16) | (g << 8) | r) >>> 0;
    }
    return out;
  }
}
