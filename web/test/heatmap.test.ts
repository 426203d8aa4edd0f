// The heat maps' twin (src/heatmap.ts) against the binary's: a render's steps and samples
// (fixtures/heatmap.json, made by `qjulia render --view steps|divergence|samples` and held
// fresh by tests/architecture/web.rs) drawn here are the PNG's heat-map rows, byte for byte.

import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, test } from 'vitest';
import { colourMap, divergenceView, samplesView, scale, stepsView } from '../src/heatmap';
import { hex } from '../src/uniform';

const fixture = JSON.parse(readFileSync(join(import.meta.dirname, 'fixtures/heatmap.json'), 'utf8'));
const { width, height } = fixture;

describe('the heat maps', () => {
  test('the colour map and its scale', () => {
    expect(colourMap(0)).toEqual([68, 1, 84]);
    expect(colourMap(1)).toEqual([253, 231, 37]);
    expect(colourMap(Number.NaN)).toEqual([68, 1, 84]);
    expect(scale(5, 5, 5)).toBe(0);
    expect(scale(9, 1, 9)).toBe(1);
  });

  test('the steps view', () => {
    expect(hex(stepsView(fixture.steps, width, height).rgb)).toBe(fixture.views.steps);
  });

  test('the divergence view', () => {
    expect(hex(divergenceView(fixture.steps, width, height).rgb)).toBe(fixture.views.divergence);
  });

  test('the samples view', () => {
    const samples: number[] = fixture.samples;
    expect(new Set(samples).size).toBeGreaterThan(1);
    expect(hex(samplesView(samples, width, height).rgb)).toBe(fixture.views.samples);
  });
});
