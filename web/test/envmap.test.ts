// The environment map's reader and packer (src/envmap.ts) against the library's: each map of
// fixtures/envmap.json (written by tests/architecture/web.rs with `qjulia::envmap`: Radiance files with new
// and old RLE and flat scanlines, OpenEXR files of half and float channels, uncompressed, RLE,
// ZIPS and ZIP, the built-in dusk.hdr, and a map halved to fit a binding) decodes and packs to
// the library's buffer bit for bit, or is refused in the library's words. One allowance: the
// halved map's irradiance coefficients that vanish by its symmetry are sums that cancel to
// 1e-13 or less, whose last bits follow the last bits of sin and cos (V8's fdlibm here, glibc's
// libm there); they agree within 1e-12, and every other float of that buffer bit for bit.

import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, test } from 'vitest';
import {
  BUILTIN_MAPS,
  crc32,
  decodeMap,
  fitBuffer,
  loadMap,
  mapFileProblem,
  mapFormat,
  type MapFormat,
  pack,
} from '../src/envmap';

interface MapCase {
  file: string | null;
  texels?: string;
  message?: string;
  width?: number;
  height?: number;
  checksum?: number;
  floats?: number;
  part_crcs?: number[];
  packed?: string;
  head?: string;
  downsampled_from?: [number, number];
}

const here = import.meta.dirname;
const FIXTURE = JSON.parse(readFileSync(join(here, 'fixtures/envmap.json'), 'utf8')) as { maps: MapCase[] };

/// A packed buffer's parts as tests/architecture/web.rs cuts them: header and irradiance, texels, marginal
/// CDF, the rows' CDFs; each part's CRC-32 of its little-endian bytes.
function partCrcs(packed: Float32Array, width: number, height: number): number[] {
  const texels = 40 + 4 * width * height;
  const marginal = texels + height + 1;
  const bytes = (a: number, b: number) => new Uint8Array(packed.buffer, packed.byteOffset + 4 * a, 4 * (b - a));
  return [bytes(0, 40), bytes(40, texels), bytes(texels, marginal), bytes(marginal, packed.length)].map(crc32);
}

/// Where two buffers first differ, as bit patterns (-1: nowhere).
function firstDifference(a: Float32Array, b: Float32Array): number {
  const [x, y] = [new Uint32Array(a.buffer, a.byteOffset, a.length), new Uint32Array(b.buffer, b.byteOffset, b.length)];
  if (x.length !== y.length) return Math.min(x.length, y.length);
  return x.findIndex((v, k) => v !== y[k]);
}

function bytesOf(file: string): Uint8Array {
  return new Uint8Array(readFileSync(join(here, 'fixtures', file)));
}

describe('the environment map', () => {
  test.each(FIXTURE.maps.filter((m) => m.file !== null).map((m) => [m.file, m] as const))('%s', async (file, m) => {
    const format = mapFormat(file!) as MapFormat;
    const bytes = bytesOf(file!);
    if (m.message !== undefined) {
      const why = await decodeMap(bytes, format).then(
        () => null,
        (e: Error) => e.message,
      );
      expect(why).toBe(m.message);
      return;
    }
    const map = await loadMap(bytes, format);
    expect([map.width, map.height, map.checksum, map.packed.length]).toEqual([m.width, m.height, m.checksum, m.floats]);
    if (m.packed !== undefined) {
      const expected = new Float32Array(Uint8Array.from(Buffer.from(m.packed, 'base64')).buffer);
      expect(firstDifference(map.packed, expected)).toBe(-1);
    }
    expect(partCrcs(map.packed, map.width, map.height)).toEqual(m.part_crcs);
  });

  test('a map past 128 MiB packed is halved as the library halves it', () => {
    const m = FIXTURE.maps.find((c) => c.texels === 'halving')!;
    const [w, h] = m.downsampled_from!;
    const texels = new Float32Array(3 * w * h);
    for (let j = 0; j < h; j++) {
      for (let i = 0; i < w; i++) texels.set([(i % 7) * 0.5, (j % 5) * 0.25, (i + j) % 3], 3 * (j * w + i));
    }
    const [width, height, halved, from] = fitBuffer(w, h, texels);
    expect([width, height, from]).toEqual([m.width, m.height, [w, h]]);
    const packed = pack(width, height, halved);
    expect(partCrcs(packed, width, height).slice(1)).toEqual(m.part_crcs!.slice(1));
    const head = new Float32Array(Uint8Array.from(Buffer.from(m.head!, 'base64')).buffer);
    const largest = Math.max(...head.map(Math.abs));
    head.forEach((x, k) => expect(Math.abs(packed[k] - x), `float ${k}`).toBeLessThanOrEqual(1e-12 * largest));
  });

  test('the built-in maps are known by their checksums', () => {
    const dusk = FIXTURE.maps.find((m) => m.file?.endsWith('dusk.hdr'))!;
    expect(BUILTIN_MAPS['dusk.hdr']).toBe(dusk.checksum);
    expect(mapFileProblem('qjulia:dusk.hdr')).toBeNull();
    expect(mapFileProblem('qjulia:dawn.hdr')).toBe('names no built-in map; they are "qjulia:dusk.hdr"');
  });

  test('the format is the extension, in any case, of the file name', () => {
    expect(mapFormat('sky.HDR')).toBe('hdr');
    expect(mapFormat('maps/sky.exr')).toBe('exr');
    for (const name of ['sky.png', '.hdr', 'dir/.exr', 'sky', 'hdr']) {
      expect(mapFormat(name)).toBe('must be an OpenEXR (.exr) or Radiance (.hdr) file');
    }
  });

  test('formats the page does not read are refused with the reason', async () => {
    const piz = bytesOf('envmap/half-zip.exr');
    // The compression attribute's value: the byte after its name, type and size.
    const at = Buffer.from(piz).indexOf('compression\0compression\0') + 24 + 4;
    piz[at] = 4;
    await expect(decodeMap(piz, 'exr')).rejects.toThrow('PIZ compression is not supported by the page');
    await expect(decodeMap(new TextEncoder().encode('not a map'), 'hdr')).rejects.toThrow(
      'not a readable Radiance .hdr file',
    );
    const hdr = bytesOf('envmap/rle.hdr');
    await expect(decodeMap(hdr.subarray(0, hdr.length - 20), 'hdr')).rejects.toThrow('not a readable Radiance .hdr file');
  });
});
