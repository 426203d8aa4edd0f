// The display transform's twin (src/display.ts) against the library's (src/display.rs): for
// each tone map and four exposures, the 8-bit value of each f32 radiance of
// fixtures/display.json (a sweep over 1e-6..1e3, negatives, the sRGB knee, and each pair of
// f32s on either side of a step of the 8-bit value), byte for byte.

import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, test } from 'vitest';
import { Display } from '../src/display';

const fixture = JSON.parse(readFileSync(join(import.meta.dirname, 'fixtures/display.json'), 'utf8')) as {
  values: number[];
  cases: { tone_map: string; exposure: number; bytes: string }[];
};

describe('the display transform', () => {
  test.each(fixture.cases.map((c) => [`${c.tone_map} at ${c.exposure} stops`, c] as const))('%s', (_, c) => {
    const d = new Display(c.exposure, c.tone_map);
    const made = fixture.values.map((v) => d.encode(Math.fround(v)).toString(16).padStart(2, '0')).join('');
    expect(made).toBe(c.bytes);
  });

  test('packs the accumulator as the frames do', () => {
    const d = new Display(0, 'none');
    const packed = d.packAll(new Float32Array([1, 0.5, 0, -3, 0, 0, 2, 9]));
    expect([...packed].map((x) => x.toString(16))).toEqual(['ff00bcff', 'ffff0000']);
  });
});
