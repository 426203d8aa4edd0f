// The uniform packing's twin (src/uniform.ts) against the binary: for every scene of the corpus
// that loads (fixtures/scenes.json, made by `qjulia gpu-params --json` and held fresh by
// tests/architecture/web.rs) and every preset, the bytes of `struct Params` for the first dispatch, its
// samples a dispatch, the path tracer's `PathParams`, the 2D view's `Julia2dParams`, and the override constants (path mode's
// the path kernel's), byte for byte and in order; and f32's precision warnings (the 3D slice's and the 2D view's), word for word.

import { describe, expect, test } from 'vitest';
import { julia2dWarnings, sliceWarnings } from '../src/precision';
import {
  firstDispatch,
  hex,
  overrides,
  packJulia2d,
  packParams,
  packPath,
  PARAMS_LAYOUT,
} from '../src/uniform';
import { CASES, load } from './corpus';

const good = CASES.filter((c) => c.message === null);

describe('the uniform', () => {
  test('the layout is the tracer uniform', () => {
    expect(PARAMS_LAYOUT.name).toBe('Params');
    expect(PARAMS_LAYOUT.fields.map((f) => f.name)).toContain('noise_target');
  });

  test('the corpus has scenes to pack', () => {
    expect(good.length).toBeGreaterThanOrEqual(20);
  });

  test.each(good.map((c) => [c.name, c] as const))('%s', (_, c) => {
    const scene = load(c);
    // The corpus names built-in maps only, which the page always has.
    const envMap = scene.get('environment.file') !== '';
    const d = firstDispatch(scene);
    expect(d.sampleEnd).toBe(c.samples_per_dispatch);
    expect(hex(packParams(scene, d, envMap))).toBe(c.bytes);
    expect(hex(packPath(scene))).toBe(c.path_bytes);
    expect(hex(packJulia2d(scene, d))).toBe(c.julia2d_bytes);
    expect(sliceWarnings(scene)).toEqual(c.warnings);
    expect(julia2dWarnings(scene)).toEqual(c.julia2d_warnings);
    expect(overrides(scene, envMap)).toEqual(c.overrides);
  });
});
