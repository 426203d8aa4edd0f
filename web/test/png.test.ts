// The PNG scene chunk (src/png.ts): the scene the binary wrote into a PNG
// (fixtures/rabbit.png, `qjulia render --preset rabbit`, held fresh by tests/architecture/web.rs) is read
// back as the binary's TOML of that scene; a chunk the page adds reads back, replaces the old
// one and keeps every other chunk; a text chunk (the page's qjulia-error) goes where the binary
// puts its own; a corrupt PNG is refused. (That the binary reads the page's
// chunk is the end-to-end tests' part: they export a PNG and render it with the CLI.)

import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, test } from 'vitest';
import { chunks, crc32, sceneOf, withScene, withText } from '../src/png';
import { SCHEMA } from '../src/scene';

const rabbit = new Uint8Array(readFileSync(join(import.meta.dirname, 'fixtures/rabbit.png')));

describe('the PNG scene chunk', () => {
  test('CRC-32 of the check string', () => {
    expect(crc32(new TextEncoder().encode('123456789'))).toBe(0xcbf43926);
  });

  test('reads the scene the binary wrote', async () => {
    const preset = SCHEMA.presets.find((p) => p.slug === 'rabbit')!;
    const toml = await sceneOf(rabbit);
    // The render's scene is the preset's at 8x6.
    expect(toml).toBe(preset.scene.replace('width = 512\nheight = 512', 'width = 8\nheight = 6'));
  });

  test('a chunk added reads back and replaces the old one', async () => {
    const added = withScene(rabbit, '[image]\nwidth = 3\n');
    expect(await sceneOf(added)).toBe('[image]\nwidth = 3\n');
    const types = (png: Uint8Array) => chunks(png).map((c) => c.type);
    // The same chunks, the scene's before the image data, where the binary writes it.
    expect(types(added)).toEqual(types(rabbit));
    expect(types(rabbit)).toEqual(['IHDR', 'iTXt', 'IDAT', 'IEND']);
  });

  test('a corrupt PNG is refused', () => {
    const broken = rabbit.slice();
    broken[40] ^= 0xff;
    expect(() => chunks(broken)).toThrow(/CRC|past the end/);
    expect(() => chunks(new Uint8Array([1, 2, 3]))).toThrow('not a PNG');
  });

  test('a text chunk goes after the image data, before the end, where the binary puts qjulia-error', () => {
    const added = withText(rabbit, 'qjulia-error', 'estimated_rmse = 0.5\n');
    const all = chunks(added);
    expect(all.map((c) => c.type)).toEqual([...chunks(rabbit).map((c) => c.type).slice(0, -1), 'tEXt', 'IEND']);
    expect(new TextDecoder().decode(all.at(-2)!.data)).toBe('qjulia-error\0estimated_rmse = 0.5\n');
    expect(added.subarray(0, rabbit.length - 12)).toEqual(rabbit.subarray(0, rabbit.length - 12));
  });
});
