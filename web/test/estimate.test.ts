// The error estimate's twin (src/estimate.ts) against the library's (src/estimate.rs and
// src/render/target.rs): each accumulator of fixtures/estimate.json gives the library's raw
// estimate, each case of the pass schedule the library's next pass, number for number (the
// same f64 bits), and each estimate the text a PNG records of it, byte for byte.

import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, test } from 'vitest';
import { errorText, nextSamples, rawEstimate } from '../src/estimate';

const fixture = JSON.parse(readFileSync(join(import.meta.dirname, 'fixtures/estimate.json'), 'utf8')) as {
  images: { width: number; height: number; planes: string; rmse: number | null; relative: number | null }[];
  schedule: { samples: number; estimate: number | null; target: number; most: number; next: number }[];
  texts: { rmse: number; relative: number; stopped_by: string | null; samples: number | null; text: string }[];
};

describe('the error estimate', () => {
  test.each(fixture.images.map((c) => [`${c.width}x${c.height}`, c] as const))('of a %s accumulator', (_, c) => {
    const bytes = Buffer.from(c.planes, 'base64');
    const planes = new Float32Array(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length));
    expect(planes.length).toBe(12 * c.width * c.height);
    const made = rawEstimate(planes, c.width);
    if (c.rmse === null) {
      expect(made).toBeNull();
    } else {
      expect(made).toEqual({ rmse: c.rmse, relative: c.relative });
    }
  });

  test('the pass schedule is the library\u2019s', () => {
    const made = fixture.schedule.map((c) => nextSamples(c.samples, c.estimate, c.target, c.most));
    expect(made).toEqual(fixture.schedule.map((c) => c.next));
    // The fixture covers what the schedule does: straight to image.samples, the least growth,
    // and more than it.
    expect(new Set(fixture.schedule.map((c) => Math.sign(c.next - 1.5 * c.samples)))).toEqual(new Set([-1, 0, 1]));
  });

  test('a PNG records an estimate as the library writes it', () => {
    for (const c of fixture.texts) {
      const target = c.stopped_by === null ? null : { stopped_by: c.stopped_by, samples: c.samples! };
      expect(errorText(c.rmse, c.relative, target)).toBe(c.text);
    }
    // Rust's Display: no exponent, however small or large.
    expect(fixture.texts.some((c) => c.text.includes('0.0000001\n'))).toBe(true);
    expect(fixture.texts.some((c) => c.text.includes('= 1000000000000000000000\n'))).toBe(true);
  });
});
