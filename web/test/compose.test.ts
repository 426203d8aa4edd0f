// The composer's twin (src/compose.ts) against the library's (src/gpu/compose.rs): every kernel
// of shaders/kernels.json composes here to the bytes the binary composes (their size and FNV-1a
// fingerprint, and the same files in the same order), generic and per variant (every 3D preset's,
// and each scene feature alone and all together: the same features on, the same constants left), and each small case of
// fixtures/kernels.json (made by tests/architecture/web_kernels.rs) gives the same text or the
// same one-line error.

import { describe, expect, test } from 'vitest';
import declaration from '../../shaders/kernels.json';
import { compose, ComposeError, fingerprint } from '../src/compose';
import { FEATURES, FILES, JULIA2D_MODULE, kernel, PATH_MODULE, SCENE_FEATURES, splitConstants, TRACE_MODULE } from '../src/shaders';
import fixture from './fixtures/kernels.json';

interface Case {
  files: Record<string, string>;
  root: string;
  on: string[];
  text: string | null;
  error: string | null;
}

describe('the composer', () => {
  test('the fingerprint is FNV-1a, 64 bits', () => {
    expect(fingerprint('')).toBe('cbf29ce484222325');
    expect(fingerprint('a')).toBe('af63dc4c8601ec8c');
    expect(fingerprint('foobar')).toBe('85944171f73967e8');
  });

  test('every kernel is declared and fixed', () => {
    expect(fixture.kernels.map((k) => k.name)).toEqual(declaration.kernels.map((k) => k.name));
  });

  test.each(fixture.kernels.map((k) => [k.name, k] as const))('kernel %s', (name, k) => {
    const d = declaration.kernels.find((x) => x.name === name)!;
    const c = compose((n) => FILES[n], FEATURES, d.root, [...d.features, ...SCENE_FEATURES]);
    expect(c.files).toEqual(k.files);
    expect(new TextEncoder().encode(c.text).length).toBe(k.bytes);
    expect(fingerprint(c.text)).toBe(k.fingerprint);
  });

  test.each(fixture.variants.map((v) => [v.what, v] as const))('variant %s', (_, v) => {
    const split = splitConstants(v.constants as [string, number][]);
    expect(split.on).toEqual(v.on);
    expect(split.left).toEqual(v.left);
    const text = kernel(v.kernel, split.on);
    expect(new TextEncoder().encode(text).length).toBe(v.bytes);
    expect(fingerprint(text)).toBe(v.fingerprint);
  });

  test('the page runs the declared kernels', () => {
    expect(TRACE_MODULE).toBe(kernel('trace'));
    expect(PATH_MODULE).toContain('fn path_main(');
    expect(JULIA2D_MODULE).toContain('alias Real = f32;');
    expect(declaration.kernels.filter((k) => k.web).map((k) => k.name)).toEqual(['trace', 'julia2d', 'path']);
  });

  test.each((fixture.cases as Case[]).map((c, i) => [i, c] as const))('case %i', (_, c) => {
    const run = () => compose((n) => c.files[n], fixture.features, c.root, c.on);
    if (c.error === null) {
      expect(run().text).toBe(c.text);
    } else {
      let message: string | null = null;
      try {
        run();
      } catch (e) {
        expect(e).toBeInstanceOf(ComposeError);
        message = (e as Error).message;
      }
      expect(message).toBe(c.error);
    }
  });
});
