// The error estimate's twin (src/estimate.ts) against the library's (src/estimate.rs and
// src/render/target.rs): each accumulator of fixtures/estimate.json gives the library's raw
// estimate, and each case of the pass schedule the library's next pass, number for number
// (the same f64 bits).

import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, test } from 'vitest';
import { nextSamples, rawEstimate } from '../src/estimate';

const fixture = JSON.parse(readFileSync(join(import.meta.dirname, 'fixtures/estimate.json'), 'utf8')) as {
  images: { width: number; height: number; planes: string; rmse: number | null; relative: number | null }[];
  schedule: { samples: number; estimate: number | null; target: number; most: number; next: number }[];
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
});
