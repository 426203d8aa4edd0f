// The uniform packing's twin (src/uniform.ts) against the binary: for every scene of the corpus
// that loads (fixtures/scenes.json, made by `qjulia gpu-params --json` and held fresh by
// tests/web.rs) and every preset, the bytes of `struct Params` for the first dispatch, its
// samples a dispatch, the path tracer's `PathParams`, and the override constants (path mode's
// the path kernel's), byte for byte and in order; and f32's precision warnings, word for word.

import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, test } from 'vitest';
import { sliceWarnings } from '../src/precision';
import { SCHEMA, SceneLoader } from '../src/scene';
import { firstDispatch, hex, overrides, packParams, packPath, PARAMS_LAYOUT } from '../src/uniform';

interface Case {
  name: string;
  preset?: string;
  file: string | null;
  sets: string[];
  message: string | null;
  bytes?: string;
  path_bytes?: string;
  warnings?: string[];
  overrides?: [string, number][];
  samples_per_dispatch?: number;
}

const here = import.meta.dirname;
const cases: Case[] = JSON.parse(readFileSync(join(here, 'fixtures/scenes.json'), 'utf8'));
const good = cases.filter((c) => c.message === null);

describe('the uniform', () => {
  test('the layout is the tracer uniform', () => {
    expect(PARAMS_LAYOUT.name).toBe('Params');
    expect(PARAMS_LAYOUT.fields.map((f) => f.name)).toContain('noise_target');
  });

  test('the corpus has scenes to pack', () => {
    expect(good.length).toBeGreaterThanOrEqual(20);
  });

  test.each(good.map((c) => [c.name, c] as const))('%s', (_, c) => {
    const loader = new SceneLoader();
    if (c.preset !== undefined) {
      const preset = SCHEMA.presets.find((p) => p.slug === c.preset)!;
      loader.tomlStr(preset.toml, { kind: 'preset', slug: preset.slug });
    }
    if (c.file !== null) {
      loader.tomlStr(readFileSync(join(here, c.file), 'utf8'), { kind: 'file', path: c.file });
    }
    for (const set of c.sets) loader.set(set);
    const scene = loader.build();
    const d = firstDispatch(scene);
    expect(d.sampleEnd).toBe(c.samples_per_dispatch);
    expect(hex(packParams(scene, d))).toBe(c.bytes);
    expect(hex(packPath(scene))).toBe(c.path_bytes);
    expect(sliceWarnings(scene)).toEqual(c.warnings);
    expect(overrides(scene)).toEqual(c.overrides);
  });
});
