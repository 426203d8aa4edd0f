// The corpus of fixtures/scenes.json (made by `qjulia gpu-params --json`, held fresh by
// tests/architecture/web.rs): each case's scene layers and what the binary made of them.

import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { SCHEMA, type Scene, SceneLoader } from '../src/scene';

export interface Case {
  name: string;
  /// Layers, in the CLI's order: a preset, a scene file (relative to test/), `--set`s.
  preset?: string;
  file: string | null;
  sets: string[];
  /// The binary's error line without `error: `, or null where it loaded the scene.
  message: string | null;
  /// Where it loaded: the resolved scene (TOML), the uniform's bytes, the path uniform's, the
  /// override constants in order, the samples a dispatch, f32's precision warnings.
  scene?: string;
  bytes?: string;
  path_bytes?: string;
  julia2d_bytes?: string;
  overrides?: [string, number][];
  samples_per_dispatch?: number;
  warnings?: string[];
  julia2d_warnings?: string[];
}

const here = import.meta.dirname;

export const CASES: Case[] = JSON.parse(readFileSync(join(here, 'fixtures/scenes.json'), 'utf8'));

/// A case's scene as the page loads it, layer by layer; throws the loader's SceneError.
export function load(c: Case): Scene {
  const loader = new SceneLoader();
  if (c.preset !== undefined) {
    const preset = SCHEMA.presets.find((p) => p.slug === c.preset)!;
    loader.tomlStr(preset.toml, { kind: 'preset', slug: preset.slug });
  }
  if (c.file !== null) {
    loader.tomlStr(readFileSync(join(here, c.file), 'utf8'), { kind: 'file', path: c.file });
  }
  for (const set of c.sets) loader.set(set);
  return loader.build();
}
