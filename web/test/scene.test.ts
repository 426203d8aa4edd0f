// The scene loader's twin (src/scene.ts) against the binary's own answers: every preset's TOML
// over the defaults gives the scene `qjulia schema --json` resolved for it, value for value, and
// each case of fixtures/scenes.json (made by `qjulia gpu-params`, held fresh by tests/architecture/web.rs)
// gives the same scene, or the same one-line message, word for word.

import { parse as parseToml } from 'smol-toml';
import { describe, expect, test } from 'vitest';
import {
  SCHEMA,
  SceneError,
  SceneLoader,
  sceneToToml,
  displayFloat,
  orthonormalise,
  type Scene,
  type Value,
} from '../src/scene';
import { CASES, load } from './corpus';

/// A resolved scene's TOML (every key written) as the loader's dotted map.
function resolved(text: string): Scene {
  const table = parseToml(text, { integersAsBigInt: true }) as { [k: string]: Value };
  const out: Scene = new Map();
  for (const key of SCHEMA.keys) {
    const v = (table[key.table] as { [k: string]: Value })[key.name];
    const plain = (x: Value): number | string | boolean =>
      typeof x === 'bigint' ? Number(x) : (x as number | string | boolean);
    out.set(key.path, Array.isArray(v) ? v.map((x) => plain(x) as number) : plain(v));
  }
  return out;
}

/// The keys where two scenes differ (none: the same, bit for bit, -0 and 0 apart).
function differences(a: Scene, b: Scene): string[] {
  return SCHEMA.keys
    .map((k) => k.path)
    .filter((path) => {
      const [x, y] = [a.get(path), b.get(path)];
      return Array.isArray(x) && Array.isArray(y)
        ? x.length !== y.length || x.some((v, k) => !Object.is(v, y[k]))
        : !Object.is(x, y);
    });
}

describe('the scene loader', () => {
  test('the schema is the one this loader reads', () => {
    expect(SCHEMA.format).toBe(1);
    expect(SCHEMA.keys.map((k) => k.path)).toContain('path.noise_target');
  });

  test.each(SCHEMA.presets.map((p) => [p.slug, p] as const))('preset %s', (_, preset) => {
    const loader = new SceneLoader();
    loader.tomlStr(preset.toml, { kind: 'preset', slug: preset.slug });
    expect(differences(loader.build(), resolved(preset.scene))).toEqual([]);
  });

  test.each(CASES.map((c) => [c.name, c] as const))('%s', (_, c) => {
    let outcome: Scene | string;
    try {
      outcome = load(c);
    } catch (e) {
      if (!(e instanceof SceneError)) throw e;
      outcome = e.message;
    }
    if (c.message !== null) {
      expect(outcome).toBe(c.message);
    } else {
      expect(typeof outcome).not.toBe('string');
      expect(differences(outcome as Scene, resolved(c.scene!))).toEqual([]);
    }
  });
});

describe('the scene writer', () => {
  // Scene::to_toml's bytes for every scene the binary loads and every preset; and what it
  // writes loads back as the same scene (the page's Save, then `qjulia render --scene`), but
  // for the slice's last bits: the loader orthonormalises the axes again, as the CLI's does.
  test.each(CASES.filter((c) => c.message === null).map((c) => [c.name, c] as const))(
    '%s',
    (_, c) => {
      const scene = load(c);
      expect(sceneToToml(scene)).toBe(c.scene);
      const again = new SceneLoader();
      again.tomlStr(sceneToToml(scene), { kind: 'file', path: 'saved.toml' });
      const reloaded = again.build();
      expect(differences(reloaded, scene).filter((k) => !k.startsWith('slice.'))).toEqual([]);
      for (const k of ['slice.x', 'slice.y', 'slice.z']) {
        const [a, b] = [reloaded.get(k) as number[], scene.get(k) as number[]];
        a.forEach((x, i) => expect(Math.abs(x - b[i])).toBeLessThan(1e-15));
      }
    },
  );

  test.each(SCHEMA.presets.map((p) => [p.slug, p] as const))('preset %s', (_, preset) => {
    const loader = new SceneLoader();
    loader.tomlStr(preset.toml, { kind: 'preset', slug: preset.slug });
    expect(sceneToToml(loader.build())).toBe(preset.scene);
  });
});

describe('the twins of the helpers', () => {
  test('floats are written as Rust writes them', () => {
    expect(displayFloat(1)).toBe('1.0');
    expect(displayFloat(-1e-31)).toBe('-0.0000000000000000000000000000001');
    expect(displayFloat(1e21)).toBe('1000000000000000000000.0');
    expect(displayFloat(0.1)).toBe('0.1');
    expect(displayFloat(Number.NaN)).toBe('nan');
  });

  test('Gram-Schmidt refuses a dependent basis and normalises the rest', () => {
    expect(orthonormalise([[1, 0, 0, 0], [2, 0, 0, 0], [0, 0, 1, 0]])).toBeNull();
    const [x, y] = orthonormalise([[2, 0, 0, 0], [1, 1, 0, 0], [0, 0, 3, 0]])!;
    expect(x).toEqual([1, 0, 0, 0]);
    expect(y).toEqual([0, 1, 0, 0]);
  });
});
