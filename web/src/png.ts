// The scene a qjulia PNG carries: an iTXt chunk with the keyword `qjulia-scene` holding the
// scene's TOML (SCENE_PNG_KEYWORD of src/scene/png.rs), as every qjulia PNG has, so that
// `qjulia render --scene FILE.png` reads a picture exported from the page back. The browser's
// encoder (canvas.toBlob) writes no such chunk: `withScene` adds it before the image data, where
// the binary writes it and where its reader (which stops at the first IDAT) looks.

/// The keyword of the iTXt chunk that carries a PNG's scene as TOML.
export const SCENE_PNG_KEYWORD = 'qjulia-scene';

const SIGNATURE = [137, 80, 78, 71, 13, 10, 26, 10];

let table: Uint32Array | null = null;

/// The CRC-32 of PNG chunks (ISO 3309, reflected, polynomial 0xEDB88320).
export function crc32(bytes: Uint8Array): number {
  if (table === null) {
    table = new Uint32Array(256);
    for (let n = 0; n < 256; n++) {
      let c = n;
      for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
      table[n] = c >>> 0;
    }
  }
  let c = 0xffffffff;
  for (const b of bytes) c = table[(c ^ b) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}

interface Chunk {
  type: string;
  data: Uint8Array;
  /// Where the chunk (its length field) starts.
  at: number;
}

/// The chunks of a PNG; throws where it is no PNG or a chunk runs past the end or fails its
/// CRC.
export function chunks(png: Uint8Array): Chunk[] {
  if (png.length < 8 || SIGNATURE.some((b, k) => png[k] !== b)) throw new Error('not a PNG');
  const view = new DataView(png.buffer, png.byteOffset, png.byteLength);
  const out: Chunk[] = [];
  let at = 8;
  while (at + 12 <= png.length) {
    const length = view.getUint32(at);
    if (at + 12 + length > png.length) throw new Error('a PNG chunk runs past the end');
    const typed = png.subarray(at + 4, at + 8 + length);
    if (crc32(typed) !== view.getUint32(at + 8 + length)) throw new Error('a PNG chunk fails its CRC');
    const type = String.fromCharCode(...png.subarray(at + 4, at + 8));
    out.push({ type, data: png.subarray(at + 8, at + 8 + length), at });
    at += 12 + length;
    if (type === 'IEND') break;
  }
  return out;
}

/// One chunk's bytes: length, type, data, CRC.
function chunk(type: string, data: Uint8Array): Uint8Array {
  const out = new Uint8Array(12 + data.length);
  const view = new DataView(out.buffer);
  view.setUint32(0, data.length);
  for (let k = 0; k < 4; k++) out[4 + k] = type.charCodeAt(k);
  out.set(data, 8);
  view.setUint32(8 + data.length, crc32(out.subarray(4, 8 + data.length)));
  return out;
}

/// `png` with the scene's TOML in an uncompressed iTXt chunk (keyword, no language, no
/// translated keyword) before the first IDAT; an existing qjulia-scene chunk is replaced.
export function withScene(png: Uint8Array, toml: string): Uint8Array<ArrayBuffer> {
  const all = chunks(png);
  if (!all.some((c) => c.type === 'IDAT')) throw new Error('a PNG without image data');
  const keyword = new TextEncoder().encode(SCENE_PNG_KEYWORD);
  const text = new TextEncoder().encode(toml);
  // keyword, 0, compression flag 0, method 0, language "", 0, translated keyword "", 0, text
  const data = new Uint8Array(keyword.length + 5 + text.length);
  data.set(keyword, 0);
  data.set(text, keyword.length + 5);
  const parts: Uint8Array[] = [png.subarray(0, 8)];
  let added = false;
  for (const c of all) {
    if (c.type === 'IDAT' && !added) {
      parts.push(chunk('iTXt', data));
      added = true;
    }
    if (c.type === 'iTXt' && isScene(c.data)) continue;
    parts.push(png.subarray(c.at, c.at + 12 + c.data.length));
  }
  const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let at = 0;
  for (const p of parts) {
    out.set(p, at);
    at += p.length;
  }
  return out;
}

/// `png` with a tEXt chunk `keyword: text` (Latin-1; here ASCII) after its image data, before
/// IEND, where the binary appends its qjulia-error chunk (src/output.rs's append_png_text).
export function withText(png: Uint8Array, keyword: string, text: string): Uint8Array<ArrayBuffer> {
  const end = chunks(png).find((c) => c.type === 'IEND');
  if (end === undefined) throw new Error('a PNG without its end');
  const data = Uint8Array.from(`${keyword}\0${text}`, (c) => c.charCodeAt(0));
  const added = chunk('tEXt', data);
  const out = new Uint8Array(png.length + added.length);
  out.set(png.subarray(0, end.at), 0);
  out.set(added, end.at);
  out.set(png.subarray(end.at), end.at + added.length);
  return out;
}

function isScene(data: Uint8Array): boolean {
  const keyword = new TextEncoder().encode(`${SCENE_PNG_KEYWORD}\0`);
  return keyword.every((b, k) => data[k] === b);
}

/// The scene TOML a qjulia PNG carries, or null where it has none. A compressed chunk is
/// inflated (zlib) with the platform's DecompressionStream.
export async function sceneOf(png: Uint8Array): Promise<string | null> {
  for (const c of chunks(png)) {
    if (c.type !== 'iTXt' || !isScene(c.data)) continue;
    let at = SCENE_PNG_KEYWORD.length + 1;
    const compressed = c.data[at] === 1;
    at += 2;
    for (let skip = 0; skip < 2; skip++) at = c.data.indexOf(0, at) + 1;
    let text = c.data.subarray(at);
    if (compressed) {
      const stream = new Blob([text.slice()]).stream().pipeThrough(new DecompressionStream('deflate'));
      text = new Uint8Array(await new Response(stream).arrayBuffer());
    }
    return new TextDecoder('utf-8', { fatal: true }).decode(text);
  }
  return null;
}
