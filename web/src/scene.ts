// The scene loader: the TypeScript twin of src/scene/load/mod.rs, written from the schema that
// `qjulia schema --json` emits (src/generated/schema.json, from the one declaration in
// src/scene/mod.rs). Layers of TOML text and `--set KEY=VALUE` over the defaults, each key read
// in the schema's order, then unknown keys refused and every range checked, with the CLI's
// one-line messages word for word (test/scene.test.ts holds them to the binary's).
//
// Twin of: SceneLoader (toml_str, set, insert_table, build_scene), Reader (read,
// reject_unknown, source_of), parse, check_range, check_scene (the ranges, the camera, the
// blades, the directions, the slice's Gram-Schmidt), Scene::set_algebra and orthonormalise;
// and of load_files (src/scene/loaded.rs): `environment.file` is checked as far as its name
// goes, and its checksum recorded or verified where the page has the map's bytes (a built-in
// map's it always has).
// TOML syntax errors are the one place the words differ: the parsers are not the same.

import { parse as parseToml } from 'smol-toml';
import { builtinChecksum, mapFileProblem } from './envmap';
import schemaJson from './generated/schema.json';
import { type V3, cross, dot, length3, normalize, sub } from './vector';

/// A TOML value as the loader keeps it: integers as bigint, floats as number (TOML tells them
/// apart, and so do the messages).
export type Value = bigint | number | string | boolean | Value[] | { [key: string]: Value };

export interface Bound {
  open?: number;
  closed?: number;
}

export interface Range {
  min: Bound | null;
  max: Bound | null;
  must_be: string;
}

export interface Key {
  path: string;
  table: string;
  name: string;
  type: 'float' | 'integer' | 'bool' | 'choice' | 'vector' | 'hyper' | 'path';
  default: number | string | boolean | number[];
  readme: string;
  range?: Range | null;
  min?: number;
  max?: number;
  must_be?: string;
  choices?: string[];
  length?: number;
  each?: Range | null;
  /// A vector that also takes one number, which every component takes (Rust's `splat`).
  splat?: boolean;
  /// The explorer's slider, where the key has one.
  slider?: { min: number; max: number; logarithmic: boolean } | null;
}

export interface Preset {
  name: string;
  slug: string;
  about: string;
  toml: string;
  two_d: boolean;
  scene: string;
}

export interface Schema {
  format: number;
  qjulia: string;
  tables: { name: string; readme: string }[];
  keys: Key[];
  messages: Record<string, string>;
  presets: Preset[];
}

export const SCHEMA = schemaJson as unknown as Schema;

/// Where a layer came from, as the messages name it (Rust's SceneSource).
export type Source =
  | { kind: 'default' }
  | { kind: 'preset'; slug: string }
  | { kind: 'file'; path: string }
  | { kind: 'flag'; flag: string }
  | { kind: 'set'; raw: string };

export function sourceText(s: Source): string {
  switch (s.kind) {
    case 'default':
      return 'default scene';
    case 'preset':
      return `preset ${s.slug}`;
    case 'file':
      return s.path;
    case 'flag':
      return s.flag;
    case 'set':
      return `--set ${s.raw}`;
  }
}

/// A scene: every key's value by its dotted path.
export type Scene = Map<string, number | string | boolean | number[]>;

/// A bad scene: the one line the CLI prints after `error: `.
export class SceneError extends Error {
  constructor(
    public source: Source,
    public key: string | null,
    message: string,
  ) {
    super(`${sourceText(source)}: ${message}`);
  }

  /// A value of `key` is wrong: in a file, `key = value: reason`; on the command line, where
  /// the value is already in view, `key reason`.
  static value(source: Source, key: string, value: Value, reason: string): SceneError {
    const onLine = source.kind === 'flag' || source.kind === 'set';
    const message = onLine ? `${key} ${reason}` : `${key} = ${displayValue(value)}: ${reason}`;
    return new SceneError(source, key, message);
  }
}

/// The default scene (Scene::default()).
export function defaultScene(): Scene {
  const s: Scene = new Map();
  for (const k of SCHEMA.keys) {
    s.set(k.path, Array.isArray(k.default) ? [...k.default] : k.default);
  }
  return s;
}

const ALGEBRA_DIM: Record<string, number> = { quaternion: 4, octonion: 8, sedenion: 16 };

/// Gram-Schmidt in x, y, z order; null where the vectors are (nearly) dependent.
export function orthonormalise(basis: number[][]): number[][] | null {
  const out: number[][] = [];
  for (const v of basis) {
    const w = [...v];
    for (const u of out) {
      const d = dot(u, w);
      for (let k = 0; k < w.length; k++) w[k] -= d * u[k];
    }
    const length = Math.sqrt(dot(w, w));
    if (Number.isNaN(length) || length <= 1e-9) return null;
    out.push(w.map((x) => x / length));
  }
  return out;
}

/// Scene::set_algebra: the numbers of the algebra take its dimension (zeros added or the tail
/// cut), and the slice's axes are made orthonormal again (the standard axes where they cannot).
export function setAlgebra(s: Scene, algebra: string): void {
  const dim = ALGEBRA_DIM[algebra];
  s.set('fractal.algebra', algebra);
  for (const path of ['fractal.c', 'slice.x', 'slice.y', 'slice.z', 'slice.offset']) {
    const v = [...(s.get(path) as number[])];
    v.length = Math.min(v.length, dim);
    while (v.length < dim) v.push(0);
    s.set(path, v);
  }
  const axes = ['slice.x', 'slice.y', 'slice.z'];
  const basis = orthonormalise(axes.map((a) => s.get(a) as number[]));
  const standard = [0, 1, 2].map((a) => Array.from({ length: dim }, (_, k) => (k === a ? 1 : 0)));
  (basis ?? standard).forEach((v, a) => s.set(axes[a], v));
}

/// Whether `key` names a table of the scene file (`[animation]` included): is_table_name.
function isTableName(key: string): boolean {
  return key === 'animation' || SCHEMA.tables.some((t) => t.name === key);
}

function isTable(v: unknown): v is { [key: string]: Value } {
  return typeof v === 'object' && v !== null && !Array.isArray(v);
}

function number(v: Value): number | null {
  if (typeof v === 'bigint') return Number(v);
  if (typeof v === 'number') return v;
  return null;
}

function contains(r: Range | null | undefined, x: number): boolean {
  if (!r) return true;
  const above = !r.min || (r.min.open !== undefined ? x > r.min.open : x >= r.min.closed!);
  const below = !r.max || (r.max.open !== undefined ? x < r.max.open : x <= r.max.closed!);
  return above && below;
}

/// Reads one value of the key's kind into the scene, or says why it is not one (Rust's
/// `parse`).
function parseValue(key: Key, v: Value, s: Scene): string | null {
  switch (key.type) {
    case 'float': {
      const x = number(v);
      if (x === null) return 'must be a number';
      if (!Number.isFinite(x)) return 'must be finite';
      s.set(key.path, x);
      return null;
    }
    case 'integer': {
      if (typeof v !== 'bigint') return 'must be an integer';
      if (v < BigInt(key.min!) || v > BigInt(key.max!)) return `must be ${key.must_be}`;
      s.set(key.path, Number(v));
      return null;
    }
    case 'bool':
      if (typeof v !== 'boolean') return 'must be true or false';
      s.set(key.path, v);
      return null;
    case 'choice':
      if (typeof v !== 'string' || !key.choices!.includes(v)) return `must be ${key.must_be}`;
      s.set(key.path, v);
      return null;
    case 'path':
      if (typeof v !== 'string') return "must be a string: a file's path";
      if (v.includes('\0')) return 'must not hold a NUL';
      s.set(key.path, v);
      return null;
    case 'vector':
    case 'hyper': {
      const len = (s.get(key.path) as number[]).length;
      const algebra = s.get('fractal.algebra') as string;
      const one = key.type === 'vector' && key.splat ? number(v) : null;
      if (one !== null) {
        // One number for every component.
        if (!Number.isFinite(one)) return 'must be finite';
        s.set(key.path, new Array<number>(len).fill(one));
        return null;
      }
      const shape =
        key.type === 'hyper' && algebra !== 'quaternion'
          ? `must be an array of ${len} numbers (fractal.algebra is "${algebra}")`
          : key.splat
            ? `must be a number or an array of ${len} numbers`
            : `must be an array of ${len} numbers`;
      if (!Array.isArray(v)) return shape;
      if (v.length !== len) return `${shape}, not ${v.length}`;
      const out: number[] = [];
      for (const item of v) {
        const x = number(item);
        if (x === null) return shape;
        if (!Number.isFinite(x)) return 'must be finite';
        out.push(x);
      }
      s.set(key.path, out);
      return null;
    }
  }
}

/// Checks the scene's value of a key against its range, after every layer is read (Rust's
/// `check_range`).
function checkRange(key: Key, s: Scene): string | null {
  if (key.type === 'float' && !contains(key.range, s.get(key.path) as number)) {
    return `must be ${key.range!.must_be}`;
  }
  if (key.type === 'vector' && (s.get(key.path) as number[]).some((x) => !contains(key.each, x))) {
    return `must have every component ${key.each!.must_be}`;
  }
  return null;
}

/// Layers of scene values over the defaults (Rust's SceneLoader): later layers win, key by key.
export class SceneLoader {
  private entries = new Map<string, [Value, Source]>();

  /// Adds a layer given as TOML text.
  tomlStr(text: string, source: Source): void {
    let table: { [key: string]: Value };
    try {
      table = parseToml(text, { integersAsBigInt: true }) as { [key: string]: Value };
    } catch (e) {
      // The TOML parsers' words differ; where they stop is the same: the line says where, as
      // the CLI's does (which then adds toml-rs's words).
      const { line, column } = e as { line?: number; column?: number };
      const where = line !== undefined && column !== undefined ? ` at line ${line}, column ${column}` : '';
      throw new SceneError(source, null, `invalid TOML${where}`);
    }
    this.insertTable('', table, source);
  }

  /// Adds one `--set KEY=VALUE`: VALUE in TOML syntax, a bare word that is not TOML taken as
  /// a string.
  set(raw: string): void {
    const source: Source = { kind: 'set', raw };
    const eq = raw.indexOf('=');
    if (eq < 0) throw new SceneError(source, null, 'expected KEY=VALUE');
    const key = raw.slice(0, eq).trim();
    if (key === '' || key.split('.').some((part) => part.trim() === '')) {
      throw new SceneError(source, null, 'expected KEY=VALUE with a dotted KEY');
    }
    const text = raw.slice(eq + 1).trim();
    let value: Value;
    try {
      const t = parseToml(`v = ${text}\n`, { integersAsBigInt: true }) as { [key: string]: Value };
      value = Object.keys(t).length === 1 && 'v' in t ? t.v : text;
    } catch {
      value = text;
    }
    // An empty inline table where a value belongs is kept, to be refused.
    if (isTable(value) && (Object.keys(value).length > 0 || isTableName(key))) this.insertTable(key, value, source);
    else this.entries.set(key, [value, source]);
  }

  private insertTable(prefix: string, table: { [key: string]: Value }, source: Source): void {
    for (const [k, v] of Object.entries(table)) {
      const key = prefix === '' ? k : `${prefix}.${k}`;
      if (isTable(v) && Object.keys(v).length > 0) this.insertTable(key, v, source);
      // A table with no keys (a template whose keys are commented out) sets nothing; an empty
      // table where a value belongs is kept, to be refused.
      else if (isTable(v) && isTableName(key)) continue;
      else this.entries.set(key, [v, source]);
    }
  }

  /// The scene: defaults overridden by every layer, then checked; throws a SceneError.
  /// `checksums`: the CRC-32 of the map `environment.file` names, where the page has its bytes
  /// (null where it has not yet: the checksum is then neither recorded nor verified).
  build(checksums: MapChecksums = builtinChecksum): Scene {
    const entries = new Map(this.entries);
    for (const k of [...entries.keys()]) {
      if (k === 'animation' || k.startsWith('animation.')) entries.delete(k);
    }
    const s = defaultScene();
    const used = new Map<string, [Value, Source]>();
    for (const key of SCHEMA.keys) {
      const entry = entries.get(key.path);
      if (entry !== undefined) {
        entries.delete(key.path);
        used.set(key.path, entry);
        const reason = parseValue(key, entry[0], s);
        if (reason !== null) throw SceneError.value(entry[1], key.path, entry[0], reason);
      }
      if (key.path === 'fractal.algebra') setAlgebra(s, s.get('fractal.algebra') as string);
    }
    rejectUnknown(entries);
    const failure = checkScene(s, (keys) => blame(keys, used));
    if (failure !== null) {
      const [key, reason] = failure;
      const [v, src] = sourceOf(key, used);
      throw SceneError.value(src, key, v, reason);
    }
    const problem = loadFiles(s, used, checksums);
    if (problem !== null) {
      const [key, reason] = problem;
      const [v, src] = sourceOf(key, used);
      throw SceneError.value(src, key, v, reason);
    }
    return s;
  }
}

/// The CRC-32 of the map file named by `environment.file`'s value, or null where the page does
/// not have its bytes.
export type MapChecksums = (file: string) => number | null;

/// The map `environment.file` names, as far as the page can tell (load_files and
/// Scene::load_environment): none where it is empty (the checksum 0); else a name that can be a
/// map, whose checksum, where the map's is known, is verified (where it is given by the file's
/// layer or a later one, and not 0) or recorded. The key at fault and the reason, or null.
function loadFiles(
  s: Scene,
  used: Map<string, [Value, Source]>,
  checksums: MapChecksums,
): [string, string] | null {
  const file = s.get('environment.file') as string;
  if (file === '') {
    s.set('environment.checksum', 0);
    return null;
  }
  const problem = mapFileProblem(file);
  if (problem !== null) return ['environment.file', problem];
  const actual = checksums(file);
  if (actual === null) return null;
  const verify =
    RANK[sourceOf('environment.checksum', used)[1].kind] >= RANK[sourceOf('environment.file', used)[1].kind];
  const recorded = s.get('environment.checksum') as number;
  if (verify && recorded !== 0 && recorded !== actual) {
    return [
      'environment.checksum',
      `is ${recorded}, but ${file}'s CRC-32 is ${actual}: the map is not the one the scene was rendered with`,
    ];
  }
  s.set('environment.checksum', actual);
  return null;
}

/// The source of a key's final value, for checks made after reading (Rust's `source_of`).
function sourceOf(key: string, used: Map<string, [Value, Source]>): [Value, Source] {
  return used.get(key) ?? ['(default)', { kind: 'default' }];
}

const RANK: Record<Source['kind'], number> = { default: 0, preset: 1, file: 2, flag: 3, set: 4 };

/// Of the keys a check involves, the one given last (the highest layer; of equals, the last
/// named, as Rust's `max_by_key`).
function blame(keys: string[], used: Map<string, [Value, Source]>): string {
  let best = keys[0];
  for (const k of keys) {
    if (RANK[sourceOf(k, used)[1].kind] >= RANK[sourceOf(best, used)[1].kind]) best = k;
  }
  return best;
}

/// How far from orthonormal a slice basis may be and still be re-orthonormalised.
export const SLICE_ORTHONORMAL_TOLERANCE = 1e-3;

/// How far from orthonormal a slice basis may be and be kept exactly as given: Gram-Schmidt's
/// own output is orthonormal to a few ulps, so a saved scene's slice loads back unchanged
/// (re-orthonormalising it would move it by an ulp each time).
export const SLICE_EXACT_TOLERANCE = 1e-14;

/// Range and consistency checks over the whole scene once every layer is in (Rust's
/// `check_scene`): the key at fault and the reason, or null; the slice basis is
/// re-orthonormalised in place.
function checkScene(s: Scene, blameOf: (keys: string[]) => string): [string, string] | null {
  for (const key of SCHEMA.keys) {
    const reason = checkRange(key, s);
    if (reason !== null) return [key.path, reason];
  }
  const v3 = (path: string) => s.get(path) as V3;
  const view = sub(v3('camera.target'), v3('camera.eye'));
  const up = v3('camera.up');
  if (length3(view) === 0 || !Number.isFinite(length3(view))) {
    return [
      blameOf(['camera.eye', 'camera.target']),
      'must differ from the other of camera.eye, camera.target',
    ];
  }
  if (length3(up) === 0) return ['camera.up', 'must not be zero'];
  if (length3(cross(normalize(view), normalize(up))) < 1e-6) {
    return [
      blameOf(['camera.up', 'camera.eye', 'camera.target']),
      'makes camera.up parallel to camera.target - camera.eye',
    ];
  }
  const blades = s.get('camera.blades') as number;
  if (blades === 1 || blades === 2) {
    return ['camera.blades', 'must be 0 (round) or in [3, 16] (a polygon)'];
  }
  for (const key of ['cut.normal', 'sky.up', 'sun.direction']) {
    if (v3(key).every((x) => x === 0)) return [key, 'must not be zero'];
  }
  const keys = ['slice.x', 'slice.y', 'slice.z'];
  const basis = keys.map((k) => s.get(k) as number[]);
  let worst = 0;
  for (let i = 0; i < 3; i++) {
    for (let j = 0; j <= i; j++) {
      const expected = i === j ? 1 : 0;
      const error = Math.abs(dot(basis[i], basis[j]) - expected);
      if (error > SLICE_ORTHONORMAL_TOLERANCE) {
        return [blameOf(keys.slice(0, i + 1)), 'makes the slice basis (x, y, z) not orthonormal'];
      }
      worst = Math.max(worst, error);
    }
  }
  if (worst <= SLICE_EXACT_TOLERANCE) return null;
  const made = orthonormalise(basis);
  if (made === null) return [blameOf(keys), 'makes the slice basis degenerate'];
  made.forEach((v, a) => s.set(keys[a], v));
  return null;
}

const KEYS = SCHEMA.keys.map((k) => k.path);

/// Whatever is left was not a scene key (Rust's `reject_unknown`): the first, in key order.
function rejectUnknown(entries: Map<string, [Value, Source]>): void {
  const left = [...entries.keys()].sort(byUtf8);
  if (left.length === 0) return;
  const key = left[0];
  const src = entries.get(key)![1];
  const tables = KEYS.map((k) => k.split('.')[0]);
  let message: string;
  if (tables.includes(key)) message = `${key} must be a table`;
  else {
    const leaf = KEYS.find((k) => key.startsWith(`${k}.`));
    message = leaf ? `${leaf} is not a table, so ${key} is an unknown key` : `unknown key ${key}`;
  }
  throw new SceneError(src, key, message);
}

/// Rust's string order (a BTreeMap's): by UTF-8 bytes, which for the BMP is by code unit.
function byUtf8(a: string, b: string): number {
  return a < b ? -1 : a > b ? 1 : 0;
}

/// A value as the toml crate displays it in a message: integers as they are, floats in Rust's
/// shortest form with no exponent and a `.0` where integral, strings quoted, arrays with ", ".
export function displayValue(v: Value): string {
  if (typeof v === 'bigint') return v.toString();
  if (typeof v === 'number') return displayFloat(v);
  if (typeof v === 'string') return JSON.stringify(v);
  if (typeof v === 'boolean') return String(v);
  if (Array.isArray(v)) return `[${v.map(displayValue).join(', ')}]`;
  const items = Object.entries(v).map(([k, x]) => `${k} = ${displayValue(x)}`);
  return items.length === 0 ? '{}' : `{ ${items.join(', ')} }`;
}

/// Rust's Display of an f64 (shortest round-trip digits, never an exponent), as TOML writes a
/// float: `.0` added to an integral value; `nan`, `inf`, `-inf`.
export function displayFloat(x: number): string {
  if (Number.isNaN(x)) return 'nan';
  if (!Number.isFinite(x)) return x > 0 ? 'inf' : '-inf';
  let text = plainDecimal(x);
  if (!/[.]/.test(text)) text += '.0';
  return text;
}

/// The shortest round-trip digits of x (JavaScript's, the same as Rust's) without an exponent.
function plainDecimal(x: number): string {
  const sign = x < 0 || Object.is(x, -0) ? '-' : '';
  const s = Math.abs(x).toString();
  const m = /^(\d)(?:\.(\d+))?e([+-]\d+)$/.exec(s);
  if (!m) return sign + s;
  const digits = m[1] + (m[2] ?? '');
  const exp = Number(m[3]);
  if (exp >= 0) {
    const whole = digits.padEnd(exp + 1, '0');
    return sign + (whole.length > exp + 1 ? `${whole.slice(0, exp + 1)}.${whole.slice(exp + 1)}` : whole);
  }
  return `${sign}0.${'0'.repeat(-exp - 1)}${digits}`;
}

/// The full scene as TOML, every key written, so that it renders again identically: the twin of
/// Scene::to_toml (the toml crate's writer): a table a section in the schema's order, a blank
/// line between them, each key as `name = value`, floats in Rust's shortest form.
export function sceneToToml(s: Scene): string {
  const sections = SCHEMA.tables.map((t) => {
    const lines = SCHEMA.keys
      .filter((k) => k.table === t.name)
      .map((k) => `${k.name} = ${tomlValue(k, s.get(k.path)!)}`);
    return `[${t.name}]\n${lines.join('\n')}\n`;
  });
  return sections.join('\n');
}

/// A key's value as the toml crate writes it.
function tomlValue(k: Key, v: number | string | boolean | number[]): string {
  if (Array.isArray(v)) return `[${v.map(displayFloat).join(', ')}]`;
  if (typeof v === 'number') return k.type === 'integer' ? String(v) : displayFloat(v);
  if (typeof v === 'string') return JSON.stringify(v);
  return String(v);
}
