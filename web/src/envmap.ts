// The environment map (`[environment]`) on the page: the twin of src/envmap.rs. Reads a Radiance
// .hdr (RGBE: new-style RLE, old-style RLE and flat scanlines, `-Y H +X W`) as the image
// crate's HdrDecoder does, and an OpenEXR file's scan lines (uncompressed, RLE, ZIPS or ZIP; half,
// float or uint channels R, G, B) as the exr crate reads them; refuses what the library refuses
// (not 2:1, wider than 8192, a texel not finite or negative); halves a map whose packed buffer
// passes 128 MiB as fit_buffer does; and packs it as `pack` does (the texels, their
// distribution, the irradiance's nine spherical harmonics: f64 sums, then f32), so that the
// Float32Array the kernels read is the library's byte for byte (test/envmap.test.ts).

/// What `environment.file` starts with to name a map built into the binary (BUILTIN_PREFIX).
export const BUILTIN_PREFIX = 'qjulia:';

/// The maps built into the binary (BUILTIN_MAPS of src/envmap.rs), by name, with the CRC-32 of
/// their bytes (tests/architecture/web.rs holds it to the library's), so that the scene loader records and
/// checks a built-in map's checksum before its bytes have arrived.
export const BUILTIN_MAPS: Record<string, number> = { 'dusk.hdr': 1760195408 };

/// The widest map taken (MAP_MAX_WIDTH).
export const MAP_MAX_WIDTH = 8192;

/// The most bytes a packed map may take (MAP_MAX_BUFFER_BYTES): WebGPU's default
/// maxStorageBufferBindingSize.
export const MAP_MAX_BUFFER_BYTES = 128 * 2 ** 20;

/// The packed buffer's layout (src/cpu/environment.rs): the size, then the irradiance's nine
/// coefficients (a vec4 slot each), then the texels.
const ENV_WIDTH = 0;
const ENV_HEIGHT = 1;
const ENV_IRRADIANCE = 4;
const ENV_TEXELS = 40;

export type MapFormat = 'exr' | 'hdr';

/// A map as decoded: `width` = 2 `height` texels of linear RGB (three floats each, row 0 at the
/// zenith) and the CRC-32 of the file's bytes.
export interface MapImage {
  width: number;
  height: number;
  texels: Float32Array;
  checksum: number;
}

/// A map packed for the kernels (EnvironmentData): its size as packed, the size it had where
/// it was halved to fit a binding, its file's CRC-32 and the buffer bound at binding 8.
export interface EnvironmentMap {
  width: number;
  height: number;
  downsampledFrom: [number, number] | null;
  checksum: number;
  packed: Float32Array<ArrayBuffer>;
}

/// The format of `environment.file`'s value by its extension (MapFormat::of, Rust's
/// Path::extension: the file name's text after its last dot, none for a name that starts
/// with its only dot), or the reason it is none.
export function mapFormat(file: string): MapFormat | string {
  const name = file.replace(/\/+$/, '').split('/').pop() ?? '';
  const dot = name.lastIndexOf('.');
  const ext = name === '..' || dot <= 0 ? '' : name.slice(dot + 1).toLowerCase();
  if (ext === 'exr' || ext === 'hdr') return ext;
  return 'must be an OpenEXR (.exr) or Radiance (.hdr) file';
}

/// What the scene loader can tell of `environment.file`'s value without its bytes (resolve):
/// a built-in map it does not know, a file of neither format; null where it may be a map.
export function mapFileProblem(file: string): string | null {
  if (file.startsWith(BUILTIN_PREFIX)) {
    if (file.slice(BUILTIN_PREFIX.length) in BUILTIN_MAPS) return null;
    const names = Object.keys(BUILTIN_MAPS).map((n) => `"${BUILTIN_PREFIX}${n}"`);
    return `names no built-in map; they are ${names.join(', ')}`;
  }
  const format = mapFormat(file);
  return format === 'exr' || format === 'hdr' ? null : format;
}

/// The CRC-32 of a built-in map named by `environment.file`'s value, or null.
export function builtinChecksum(file: string): number | null {
  if (!file.startsWith(BUILTIN_PREFIX)) return null;
  return BUILTIN_MAPS[file.slice(BUILTIN_PREFIX.length)] ?? null;
}

const CRC_TABLE = Uint32Array.from({ length: 256 }, (_, n) => {
  let c = n;
  for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});

/// The CRC-32 (IEEE) of `bytes`, as crc32fast::hash.
export function crc32(bytes: Uint8Array): number {
  let c = 0xffffffff;
  for (const b of bytes) c = CRC_TABLE[(c ^ b) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}

/// The size checks a map's header allows before its pixels are read (check_size; the host's
/// memory is not known here: the halving keeps the buffer within a binding).
function checkSize(width: number, height: number): void {
  if (width === 0 || height === 0 || width !== 2 * height) {
    throw new Error(`is ${width}x${height}: an equirectangular map is exactly twice as wide as it is high`);
  }
  if (width > MAP_MAX_WIDTH) {
    throw new Error(`is ${width}x${height}: at most ${MAP_MAX_WIDTH} wide (downsample it)`);
  }
}

/// A map file's bytes decoded and checked (from_bytes), or an Error with the reason.
export async function decodeMap(bytes: Uint8Array, format: MapFormat): Promise<MapImage> {
  const [width, height, texels] = format === 'hdr' ? readHdr(bytes) : await readExr(bytes);
  for (let k = 0; k < texels.length; k += 3) {
    const t = [texels[k], texels[k + 1], texels[k + 2]];
    if (t.some((c) => !Number.isFinite(c) || c < 0)) {
      const i = k / 3;
      throw new Error(
        `texel (${i % width}, ${Math.floor(i / width)}) is [${t.map(f32Debug).join(', ')}]: every channel must be finite and >= 0`,
      );
    }
  }
  return { width, height, texels, checksum: crc32(bytes) };
}

/// Rust's Debug of an f32: the shortest digits that read back as it, in exponent form below
/// 1e-4 and from 1e16.
function f32Debug(x: number): string {
  if (Number.isNaN(x)) return 'NaN';
  if (!Number.isFinite(x)) return x > 0 ? 'inf' : '-inf';
  if (x === 0) return Object.is(x, -0) ? '-0.0' : '0.0';
  let p = 1;
  while (Math.fround(Number(x.toPrecision(p))) !== x) p++;
  const shortest = Number(x.toPrecision(p));
  const abs = Math.abs(shortest);
  if (abs >= 1e-4 && abs < 1e16) {
    const plain = shortest.toFixed(Math.max(0, p - 1 - Math.floor(Math.log10(abs)))).replace(/(\.\d*?)0+$/, '$1');
    return /\./.test(plain) && !plain.endsWith('.') ? plain : `${plain.replace(/\.$/, '')}.0`;
  }
  return shortest.toExponential().replace('e+', 'e');
}

/// The map decoded, halved to fit a binding and packed (load_source's work on the bytes).
export async function loadMap(bytes: Uint8Array, format: MapFormat): Promise<EnvironmentMap> {
  const image = await decodeMap(bytes, format);
  const [width, height, texels, downsampledFrom] = fitBuffer(image.width, image.height, image.texels);
  return { width, height, downsampledFrom, checksum: image.checksum, packed: pack(width, height, texels) };
}

/// The notice a halved map gives, where it was (EnvironmentData::notice), `name` its file.
export function mapNotice(map: EnvironmentMap, name: string): string | null {
  if (map.downsampledFrom === null) return null;
  const [w, h] = map.downsampledFrom;
  return (
    `environment.file ${name}: ${w}x${h} would pack to more than one GPU binding holds ` +
    `(${MAP_MAX_BUFFER_BYTES / 2 ** 20} MiB), so it was halved to ${map.width}x${map.height}`
  );
}

// --- Radiance .hdr: the image crate's HdrDecoder (strict) ---

/// A Radiance RGBE file as linear RGB, row 0 at the top (read_hdr).
export function readHdr(bytes: Uint8Array): [number, number, Float32Array] {
  const fail = (why: string) => new Error(`not a readable Radiance .hdr file: ${why}`);
  let at = 0;
  /// A line without its "\n"; null at the end of the file.
  const line = (): string | null => {
    if (at >= bytes.length) return null;
    const end = bytes.indexOf(0x0a, at);
    const stop = end < 0 ? bytes.length : end;
    const text = new TextDecoder().decode(bytes.subarray(at, stop));
    at = end < 0 ? bytes.length : end + 1;
    return text;
  };
  if (new TextDecoder().decode(bytes.subarray(0, 10)) !== '#?RADIANCE') {
    throw fail('Radiance HDR signature not found');
  }
  at = 10;
  line();
  for (;;) {
    const l = line();
    if (l === null) throw fail('EOF in header');
    if (l === '') break;
    if (l.startsWith('#')) continue;
    headerLine(l, fail);
  }
  const dims = line();
  if (dims === null) throw fail('EOF in dimensions line');
  const parts = dims.split(/\s+/).filter((p) => p !== '');
  if (parts.length < 4) throw fail(`dimensions line too short: have ${parts.length} elements, expected 4`);
  if (parts.length > 4) throw fail('dimensions line contains too many elements, expected 4');
  if (parts[0] !== '-Y' || parts[2] !== '+X') throw fail(`orientation ${parts[0]} ${parts[2]} is not supported`);
  const u32 = (s: string) => (/^\+?\d+$/.test(s) && Number(s) <= 0xffffffff ? Number(s) : NaN);
  const [height, width] = [u32(parts[1]), u32(parts[3])];
  if (Number.isNaN(height) || Number.isNaN(width)) throw fail('cannot parse the dimensions');
  checkSize(width, height);
  const out = new Float32Array(3 * width * height);
  const line4 = new Uint8Array(4 * width);
  const byte = () => {
    if (at >= bytes.length) throw fail('unexpected end of file');
    return bytes[at++];
  };
  for (let j = 0; j < height; j++) {
    readScanline(line4, width, byte, fail);
    for (let i = 0; i < width; i++) {
      const e = line4[4 * i + 3];
      // 2^(e - 136), as Rgbe8Pixel::to_hdr builds it (0 for e = 0); the products are exact.
      const scale = e === 0 ? 0 : 2 ** (e - 136);
      for (let c = 0; c < 3; c++) out[3 * (j * width + i) + c] = line4[4 * i + c] * scale;
    }
  }
  return [width, height, out];
}

/// One header line (update_header_info, strict): FORMAT must be RGBE; EXPOSURE, PIXASPECT and
/// COLORCORR must hold numbers.
function headerLine(line: string, fail: (why: string) => Error): void {
  const eq = line.indexOf('=');
  if (eq <= 0 || eq >= line.length - 1) return;
  const key = line.slice(0, eq).trim();
  const value = line.slice(eq + 1).trim();
  const float = (s: string) => /^[+-]?(\d+\.?\d*([eE][+-]?\d+)?|\.\d+([eE][+-]?\d+)?|inf|infinity|nan)$/i.test(s);
  if (key === 'FORMAT' && value !== '32-bit_rle_rgbe') throw fail(`the format ${value} is not supported`);
  if ((key === 'EXPOSURE' || key === 'PIXASPECT') && !float(value)) throw fail(`cannot parse ${key}`);
  if (key === 'COLORCORR') {
    const numbers = value.split(/\s+/).filter((p) => p !== '');
    if (numbers.length < 3 || !numbers.slice(0, 3).every(float)) throw fail('cannot parse COLORCORR');
    if (numbers.length > 3) throw fail('extraneous COLORCORR numbers');
  }
}

/// One scanline of RGBE pixels into `line` (read_scanline): new-style RLE where its first
/// pixel is (2, 2, < 128, _), else old-style RLE or flat.
function readScanline(line: Uint8Array, width: number, byte: () => number, fail: (why: string) => Error): void {
  const first = [byte(), byte(), byte(), byte()];
  if (first[0] === 2 && first[1] === 2 && first[2] < 128) {
    for (let c = 0; c < 4; c++) {
      let pos = 0;
      while (pos < width) {
        let run = byte();
        const repeat = run > 128;
        if (repeat) run -= 128;
        if (pos + run > width) throw fail(`wrong scanline length: ${pos + run}, expected ${width}`);
        if (repeat) {
          const value = byte();
          for (let k = 0; k < run; k++) line[4 * (pos + k) + c] = value;
        } else {
          for (let k = 0; k < run; k++) line[4 * (pos + k) + c] = byte();
        }
        pos += run;
      }
    }
    return;
  }
  // Old-style: a pixel (1, 1, 1, n) repeats the one before n times, times 256 for each such
  // pixel before it in a row.
  const isRun = (p: number[]) => p[0] === 1 && p[1] === 1 && p[2] === 1;
  if (isRun(first)) throw fail('first pixel of a scanline is a run length marker');
  line.set(first, 0);
  let previous = first;
  let x = 1;
  let multiplier = 1;
  while (x < width) {
    const p = [byte(), byte(), byte(), byte()];
    if (isRun(p)) {
      const run = p[3] * multiplier;
      multiplier *= 256;
      if (x + run > width) throw fail(`wrong scanline length: ${x + run}, expected ${width}`);
      for (let k = 0; k < run; k++) line.set(previous, 4 * (x + k));
      x += run;
    } else {
      multiplier = 1;
      previous = p;
      line.set(p, 4 * x);
      x += 1;
    }
  }
}

// --- OpenEXR: single-part scan lines, as the exr crate reads R, G, B ---

/// Compression methods by their code, with the scan lines a block holds; the page reads the
/// first four.
const EXR_COMPRESSION = ['none', 'RLE', 'ZIPS', 'ZIP', 'PIZ', 'PXR24', 'B44', 'B44A', 'DWAA', 'DWAB'];
const EXR_LINES_PER_BLOCK = [1, 1, 1, 16, 32, 16, 32, 32, 32, 256];
/// Bytes a sample of each pixel type takes: uint, half, float.
const EXR_SAMPLE_BYTES = [4, 2, 4];

interface ExrChannel {
  name: string;
  type: number;
}

/// An OpenEXR file's R, G and B as linear RGB, row 0 at the top of the data window (read_exr).
/// Single-part scan-line files, uncompressed or RLE, ZIPS or ZIP compressed: anything else is
/// refused with the reason.
export async function readExr(bytes: Uint8Array): Promise<[number, number, Float32Array]> {
  const fail = (why: string) => new Error(`not a readable OpenEXR file: ${why}`);
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let at = 0;
  const need = (n: number) => {
    if (at + n > bytes.length) throw fail('the file ends too early');
  };
  const i32 = () => (need(4), (at += 4), view.getInt32(at - 4, true));
  const text = () => {
    const end = bytes.indexOf(0, at);
    if (end < 0) throw fail('the file ends too early');
    const s = new TextDecoder().decode(bytes.subarray(at, end));
    at = end + 1;
    return s;
  };
  if (i32() !== 20000630) throw fail('not an OpenEXR file (no magic number)');
  const version = i32();
  if ((version & 0xff) !== 2) throw fail(`version ${version & 0xff} is not supported`);
  if (version & 0x1000) throw fail('multi-part files are not supported by the page (the command line reads them)');
  if (version & 0x800) throw fail('deep data is not supported');
  if (version & 0x200) throw fail('tiled files are not supported by the page (the command line reads them)');
  let channels: ExrChannel[] | null = null;
  let compression = -1;
  let window: number[] | null = null;
  for (;;) {
    const name = text();
    if (name === '') break;
    text();
    const size = i32();
    need(size);
    const start = at;
    if (name === 'channels') {
      channels = [];
      for (;;) {
        const channel = text();
        if (channel === '') break;
        const type = i32();
        // pLinear and three reserved bytes.
        at += 4;
        const [xs, ys] = [i32(), i32()];
        if (xs !== 1 || ys !== 1) throw fail(`channel ${channel} is subsampled, which is not supported`);
        channels.push({ name: channel, type });
      }
    } else if (name === 'compression') {
      compression = bytes[at];
    } else if (name === 'dataWindow') {
      window = [i32(), i32(), i32(), i32()];
    }
    at = start + size;
  }
  if (channels === null || window === null || compression < 0) throw fail('a required header attribute is missing');
  const method = EXR_COMPRESSION[compression] ?? `code ${compression}`;
  if (compression > 3) throw fail(`${method} compression is not supported by the page (uncompressed, RLE, ZIPS and ZIP are)`);
  if (channels.some((c) => c.type < 0 || c.type > 2)) throw fail('a channel has an unknown pixel type');
  const [xMin, yMin, xMax, yMax] = window;
  const width = xMax - xMin + 1;
  const height = yMax - yMin + 1;
  if (width <= 0 || height <= 0) throw fail('the data window is empty');
  checkSize(width, height);
  const rgb = ['R', 'G', 'B'].map((n) => channels.findIndex((c) => c.name === n));
  if (rgb.some((k) => k < 0)) throw fail('it has no R, G and B channels');
  const linesPerBlock = EXR_LINES_PER_BLOCK[compression];
  const blocks = Math.ceil(height / linesPerBlock);
  need(8 * blocks);
  const offsets = Array.from({ length: blocks }, (_, k) => Number(view.getBigUint64(at + 8 * k, true)));
  const lineBytes = channels.reduce((n, c) => n + width * EXR_SAMPLE_BYTES[c.type], 0);
  const out = new Float32Array(3 * width * height);
  for (const offset of offsets) {
    at = offset;
    const y = i32() - yMin;
    const size = i32();
    if (y < 0 || y >= height || size < 0) throw fail('a block lies outside the data window');
    need(size);
    const lines = Math.min(linesPerBlock, height - y);
    const data = await uncompress(bytes.subarray(at, at + size), compression, lines * lineBytes, fail);
    const block = new DataView(data.buffer, data.byteOffset, data.byteLength);
    let p = 0;
    for (let l = 0; l < lines; l++) {
      for (let c = 0; c < channels.length; c++) {
        const type = channels[c].type;
        const slot = rgb.indexOf(c);
        for (let i = 0; i < width; i++) {
          if (slot >= 0) {
            const v =
              type === 1 ? half(block.getUint16(p, true)) : type === 2 ? block.getFloat32(p, true) : block.getUint32(p, true);
            out[3 * ((y + l) * width + i) + slot] = v;
          }
          p += EXR_SAMPLE_BYTES[type];
        }
      }
    }
  }
  return [width, height, out];
}

/// A block's bytes as stored: raw where they take the uncompressed size (the exr crate's test),
/// else run-length or zlib decoded, then the predictor undone and the two halves interleaved.
async function uncompress(
  data: Uint8Array,
  compression: number,
  size: number,
  fail: (why: string) => Error,
): Promise<Uint8Array> {
  if (data.length === size) return data;
  if (compression === 0) throw fail('an uncompressed block has the wrong size');
  const packed = compression === 1 ? unRle(data) : await inflate(data);
  if (packed.length !== size) throw fail('a block decompresses to the wrong size');
  for (let k = 1; k < size; k++) packed[k] = (packed[k - 1] + packed[k] - 128) & 0xff;
  const out = new Uint8Array(size);
  const half = (size + 1) >> 1;
  for (let k = 0; k < size; k++) out[k] = k % 2 === 0 ? packed[k >> 1] : packed[half + (k >> 1)];
  return out;
}

/// OpenEXR's run-length code: a negative count copies that many bytes, a count n >= 0 repeats
/// the next byte n + 1 times.
function unRle(data: Uint8Array): Uint8Array {
  const out: number[] = [];
  let at = 0;
  while (at < data.length) {
    const count = (data[at++] << 24) >> 24;
    if (count < 0) {
      for (let k = 0; k < -count; k++) out.push(data[at++]);
    } else {
      const value = data[at++];
      for (let k = 0; k <= count; k++) out.push(value);
    }
  }
  return Uint8Array.from(out);
}

/// zlib's inflate, by the platform's DecompressionStream.
async function inflate(data: Uint8Array): Promise<Uint8Array> {
  const stream = new Blob([data as BlobPart]).stream().pipeThrough(new DecompressionStream('deflate'));
  return new Uint8Array(await new Response(stream).arrayBuffer());
}

/// An IEEE half's value.
function half(bits: number): number {
  const sign = bits & 0x8000 ? -1 : 1;
  const exponent = (bits >> 10) & 0x1f;
  const fraction = bits & 0x3ff;
  if (exponent === 0) return sign * fraction * 2 ** -24;
  if (exponent === 31) return fraction === 0 ? sign * Infinity : NaN;
  return sign * (1 + fraction / 1024) * 2 ** (exponent - 15);
}

// --- Packing: src/envmap.rs's fit_buffer, Distribution1d, pack, irradiance_coefficients ---

/// Floats of a `width` x `height` map packed (packed_floats).
export function packedFloats(width: number, height: number): number {
  return ENV_TEXELS + 5 * width * height + 2 * height + 1;
}

/// The map halved (each texel the mean of 2 x 2, summed in f64) until it packs within
/// MAP_MAX_BUFFER_BYTES: its size, texels, and the size it had where it was halved.
export function fitBuffer(
  width: number,
  height: number,
  texels: Float32Array,
): [number, number, Float32Array, [number, number] | null] {
  let [w, h, t] = [width, height, texels];
  while (packedFloats(w, h) * 4 > MAP_MAX_BUFFER_BYTES && h > 1) {
    const [hw, hh] = [Math.floor(w / 2), Math.floor(h / 2)];
    const out = new Float32Array(3 * hw * hh);
    for (let j = 0; j < hh; j++) {
      for (let i = 0; i < hw; i++) {
        for (let c = 0; c < 3; c++) {
          const s = (x: number, y: number) => t[3 * (y * w + x) + c];
          const sum = s(2 * i, 2 * j) + s(2 * i + 1, 2 * j) + s(2 * i, 2 * j + 1) + s(2 * i + 1, 2 * j + 1);
          out[3 * (j * hw + i) + c] = sum / 4;
        }
      }
    }
    [w, h, t] = [hw, hh, out];
  }
  return [w, h, t, w !== width || h !== height ? [width, height] : null];
}

const f32 = Math.fround;

/// A piecewise-constant distribution over [0, 1) (Distribution1d): the CDF and the mean in f64,
/// kept in f32.
class Distribution1d {
  readonly cdf: Float32Array;
  readonly integral: number;

  constructor(readonly func: Float32Array) {
    const n = func.length;
    const cdf = new Float64Array(n + 1);
    for (let k = 0; k < n; k++) cdf[k + 1] = cdf[k] + func[k] / n;
    const integral = cdf[n];
    this.cdf = Float32Array.from(cdf, (c, k) => (integral > 0 ? c / integral : k / n));
    this.integral = f32(integral);
  }

  /// The density of piece k (1, uniform, for a distribution of no mass).
  pdfPiece(k: number): number {
    return this.integral > 0 ? f32(this.func[k] / this.integral) : 1;
  }
}

const LUMINANCE = [f32(0.2126), f32(0.7152), f32(0.0722)];

/// Rec. 709 luminance in f32 arithmetic, as the sampling weighs texels.
function luminance(t: Float32Array, k: number): number {
  return f32(f32(f32(LUMINANCE[0] * t[k]) + f32(LUMINANCE[1] * t[k + 1])) + f32(LUMINANCE[2] * t[k + 2]));
}

/// The kernels' buffer of a `width` x `height` map (pack): the size; the irradiance's nine
/// coefficients; each texel's RGB and density; the marginal CDF over rows; each row's CDF.
export function pack(width: number, height: number, texels: Float32Array): Float32Array<ArrayBuffer> {
  const rows: Distribution1d[] = [];
  for (let j = 0; j < height; j++) {
    const sinRow = Math.sin((Math.PI * (j + 0.5)) / height);
    const func = new Float32Array(width);
    for (let i = 0; i < width; i++) func[i] = Math.max(luminance(texels, 3 * (j * width + i)), 0) * sinRow;
    rows.push(new Distribution1d(func));
  }
  const marginal = new Distribution1d(Float32Array.from(rows, (r) => r.integral));
  const out = new Float32Array(packedFloats(width, height));
  out[ENV_WIDTH] = width;
  out[ENV_HEIGHT] = height;
  irradianceCoefficients(width, height, texels).forEach((c, k) => out.set(c, ENV_IRRADIANCE + 4 * k));
  for (let j = 0; j < height; j++) {
    const pj = marginal.pdfPiece(j);
    for (let i = 0; i < width; i++) {
      const k = j * width + i;
      const at = ENV_TEXELS + 4 * k;
      out.set(texels.subarray(3 * k, 3 * k + 3), at);
      out[at + 3] = pj * rows[j].pdfPiece(i);
    }
  }
  const marginalAt = ENV_TEXELS + 4 * width * height;
  out.set(marginal.cdf, marginalAt);
  rows.forEach((row, j) => out.set(row.cdf, marginalAt + height + 1 + j * (width + 1)));
  return out;
}

/// The irradiance's nine coefficients (RGB each, f64) as pack stores them
/// (irradiance_coefficients): the map projected on the real spherical harmonics of bands 0 to
/// 2, each texel weighed by its exact solid angle, times A_l / pi and the basis' constant.
export function irradianceCoefficients(width: number, height: number, texels: Float32Array): number[][] {
  const PI = Math.PI;
  const c0 = 0.2820947917738781;
  const c1 = 0.4886025119029199;
  const c2 = 1.0925484305920792;
  const c20 = 0.31539156525252;
  const c22 = 0.5462742152960396;
  const band1 = (c1 * c1 * 2.0) / 3.0;
  const band2 = (c2 * c2) / 4.0;
  const scale = [c0 * c0, band1, band1, band1, band2, band2, (c20 * c20) / 4.0, band2, (c22 * c22) / 4.0];
  const sums = Array.from({ length: 9 }, () => [0, 0, 0]);
  for (let j = 0; j < height; j++) {
    const t0 = (PI * j) / height;
    const t1 = (PI * (j + 1)) / height;
    const omega = ((2.0 * PI) / width) * (Math.cos(t0) - Math.cos(t1));
    const theta = 0.5 * (t0 + t1);
    const [sinTheta, z] = [Math.sin(theta), Math.cos(theta)];
    for (let i = 0; i < width; i++) {
      const phi = (2.0 * PI * (i + 0.5)) / width;
      const x = sinTheta * Math.cos(phi);
      const y = sinTheta * Math.sin(phi);
      const basis = [1.0, y, z, x, x * y, y * z, 3.0 * z * z - 1.0, x * z, x * x - y * y];
      const k = 3 * (j * width + i);
      for (let b = 0; b < 9; b++) {
        for (let c = 0; c < 3; c++) sums[b][c] += texels[k + c] * basis[b] * omega;
      }
    }
  }
  return sums.map((s, k) => s.map((v) => v * scale[k]));
}
