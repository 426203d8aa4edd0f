// The WGSL composer's twin (src/gpu/compose.rs): each file of shaders/ names what it needs with
// `#import` lines and gates its own text with `#if`, and a kernel is its root file composed for
// a set of features, before WebGPU's parser sees it. The rules are the Rust module's, line for
// line; test/compose.test.ts holds the composed kernels to the binary's byte for byte
// (test/fixtures/kernels.json, made by tests/architecture/web.rs).

/// A kernel composed: its text and the files it holds, in the order they were appended.
export interface Composed {
  text: string;
  files: string[];
}

/// Why a kernel cannot be composed: one line naming the file and its line.
export class ComposeError extends Error {}

interface Evaluated {
  imports: string[];
  kept: string[];
}

/// The kernel rooted at `root` with the features `on` (each one of `features`, the declared set)
/// turned on, from `files` (a name to its text, undefined where no such file is).
export function compose(
  files: (name: string) => string | undefined,
  features: readonly string[],
  root: string,
  on: readonly string[],
): Composed {
  const unknown = on.find((f) => !features.includes(f));
  if (unknown !== undefined) throw new ComposeError(`unknown feature \`${unknown}\``);
  const done: string[] = [];
  const open: string[] = [];
  const parts: string[] = [];
  const visit = (name: string, from: string | null): void => {
    if (done.includes(name)) return;
    if (open.includes(name)) {
      const chain = open.slice(open.indexOf(name)).join(' -> ');
      throw new ComposeError(`shaders/${name}.wgsl imports itself: ${chain} -> ${name}`);
    }
    const text = files(name);
    if (text === undefined) {
      const by = from === null ? '' : ` (imported by ${from})`;
      throw new ComposeError(`no shader file shaders/${name}.wgsl${by}`);
    }
    open.push(name);
    const evaluated = evaluate(name, text, features, on);
    for (const i of evaluated.imports) visit(i, `shaders/${name}.wgsl`);
    open.pop();
    done.push(name);
    parts.push(evaluated.kept.join('\n'));
  };
  visit(root, null);
  return { text: parts.join('\n'), files: done };
}

/// `text`'s lines with its conditions evaluated for `on`: the imports counted and the other lines
/// kept.
function evaluate(name: string, text: string, features: readonly string[], on: readonly string[]): Evaluated {
  const fail = (line: number, what: string): never => {
    throw new ComposeError(`shaders/${name}.wgsl:${line + 1}: ${what}`);
  };
  // Each open `#if`: whether its branch now counts, and whether an `#else` was seen.
  const conditions: { holds: boolean; seen: boolean }[] = [];
  const out: Evaluated = { imports: [], kept: [] };
  const lines = text.split('\n');
  lines.forEach((line, n) => {
    const counts = conditions.every((c) => c.holds);
    if (!line.startsWith('#')) {
      if (counts) out.kept.push(line);
      return;
    }
    const words = line.slice(1).split(/\s+/).filter((w) => w !== '');
    if (words.length === 2 && words[0] === 'import') {
      if (counts) out.imports.push(words[1]);
    } else if (words.length === 2 && words[0] === 'if') {
      const negated = words[1].startsWith('!');
      const feature = negated ? words[1].slice(1) : words[1];
      if (!features.includes(feature)) fail(n, `unknown feature \`${feature}\``);
      conditions.push({ holds: on.includes(feature) !== negated, seen: false });
    } else if (words.length === 1 && words[0] === 'else') {
      const last = conditions[conditions.length - 1];
      if (last === undefined) fail(n, '`#else` without `#if`');
      if (last.seen) fail(n, 'a second `#else`');
      last.holds = !last.holds;
      last.seen = true;
    } else if (words.length === 1 && words[0] === 'endif') {
      if (conditions.pop() === undefined) fail(n, '`#endif` without `#if`');
    } else {
      fail(n, `unknown directive \`${line.trimEnd()}\``);
    }
  });
  if (conditions.length > 0) fail(lines.length - 1, '`#if` without `#endif`');
  return out;
}

/// The 64-bit FNV-1a hash of `text`'s UTF-8 bytes, as 16 lowercase hex digits: a kernel's
/// fingerprint (the twin of `compose::fingerprint`).
export function fingerprint(text: string): string {
  let h = 0xcbf29ce484222325n;
  for (const b of new TextEncoder().encode(text)) {
    h ^= BigInt(b);
    h = (h * 0x100000001b3n) & 0xffffffffffffffffn;
  }
  return h.toString(16).padStart(16, '0');
}
