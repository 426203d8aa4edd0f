//! No import cycle between the crate's files: every path into the crate in src/ is resolved to
//! the file that defines what it names, and the graph of those file-to-file edges must be acyclic.
//!
//! How it reads the sources (plain string scanning, no parser crate):
//! - Comments, string literals (raw and byte ones too) and char literals are blanked first.
//! - The module tree is followed from the crate roots (src/lib.rs, and src/main.rs for the
//!   binary) through `mod x;` declarations (src/x.rs or src/x/mod.rs); an inline `mod x { .. }`
//!   (a test module) is a module of its own that lives in its parent's file.
//! - References are `use` declarations (grouped trees like `use crate::{a, b::{c, d as e}}`
//!   included) and paths in code (`crate::memory::human(..)`, `super::x::f()`, and paths that
//!   start with a child module's name or a name a `use` brought in).
//! - A path is resolved through the module tree: down through the modules it names, then through
//!   the `use` declarations of the module it reached (re-exports followed, chain by chain), to the
//!   module that defines the item; `crate::a::b::Item` belongs to the deepest module on the way.
//! - Edges: file A -> file B when A uses something B defines. A `pub use` re-export is an alias,
//!   not a use: it makes an edge only if the re-exporting file also uses the name itself. A `use`
//!   of a module as a namespace (`use crate::cpu;`) makes no edge by itself; the paths through it
//!   (`cpu::trace::f()`) do. `use super::*` is an edge to the parent's file.
//! - Unit tests (`#[cfg(test)] mod tests`, inline or a file) are leaves: nothing imports them,
//!   so their paths cannot close a cycle and are left out.
//! - Parent and child: `mod x;` is ownership, not an edge. A child that uses its parent's items
//!   (`use super::Scene`) has an edge to the parent; that is fine as long as the parent does not
//!   use the child's items (through the child's re-export or not): then the two form a cycle.
//!
//! On failure it prints each cycle as a chain of files with the path behind each edge.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fs;
use std::path::{Path, PathBuf};

/// Known cycles, each broken here at one edge: "FROM -> TO: WHY". The test fails when an entry
/// is no longer needed (the edge is gone, or no cycle runs through it), so that the list only
/// shrinks; it may not grow. Cut one by moving what both sides use into a module of its own.
///
/// The one left is the scene's declaration and its schema, which are one definition in two
/// files: `scene_schema!` (schema/mod.rs) expands the key declarations in scene/mod.rs into the
/// `Scene` struct and, beside it, the tables `SCHEMA`, `TABLES` and `KEYS` of the schema's
/// `Key`s, whose `Kind` reads and writes each key in a `Scene` (`At`'s `fn(&Scene)`). The
/// declarations name the schema's `Range`, and the macro's body its `Key`, `Kind`, `At`,
/// `Table` and `Slider`; the schema names `Scene`, and finds a key in `SCHEMA` (`key`). No
/// module can sit between them: the edge goes only where the declaration and those types share
/// one file (the declaration moved into schema/mod.rs, beside the macros and the types).
const ALLOWED: &[&str] = &[
    "src/scene/schema/mod.rs -> src/scene/mod.rs: the schema's Kind reads and writes a Scene \
     (At's fn(&Scene)) and key() searches SCHEMA, while Scene and SCHEMA, TABLES and KEYS are \
     made together in scene/mod.rs by the schema's scene_schema! macro from the declarations",
];

/// An entry of [`ALLOWED`] as (from, to).
fn allowed(entry: &str) -> (&str, &str) {
    let (edge, _why) = entry.split_once(": ").expect("FROM -> TO: WHY");
    edge.split_once(" -> ").expect("FROM -> TO: WHY")
}

type ModPath = Vec<String>;
/// File -> file it uses -> the first path that made the edge.
type Graph = BTreeMap<String, BTreeMap<String, String>>;

/// One `use` leaf: the name it binds in its module and the path as written.
#[derive(Debug, Clone)]
struct UseDecl {
    local: String,
    path: Vec<String>,
    glob: bool,
    public: bool,
}

#[derive(Debug, Default)]
struct Module {
    file: PathBuf,
    children: BTreeSet<String>,
    uses: Vec<UseDecl>,
}

/// A path found in a file: the module it was written in and its segments.
struct Ref {
    module: ModPath,
    path: Vec<String>,
    from_use: Option<UseDecl>,
}

/// Blanks comments, string and char literals (newlines kept), so what is left is code.
fn strip(src: &str) -> String {
    let c: Vec<char> = src.chars().collect();
    let at = |k: usize, ch: char| c.get(k) == Some(&ch);
    let mut out: Vec<char> = Vec::with_capacity(c.len());
    let mut i = 0;
    while i < c.len() {
        let ident_before = i > 0 && (c[i - 1].is_alphanumeric() || c[i - 1] == '_');
        let raw = match (c[i], at(i + 1, 'r')) {
            ('r', _) => i + 1,
            ('b', true) => i + 2,
            _ => 0,
        };
        let hashes = (raw..c.len())
            .take_while(|&j| raw > 0 && c[j] == '#')
            .count();
        let end = if at(i, '/') && at(i + 1, '/') {
            (i..c.len()).find(|&j| c[j] == '\n').unwrap_or(c.len())
        } else if at(i, '/') && at(i + 1, '*') {
            let (mut depth, mut j) = (1, i + 2);
            while j < c.len() && depth > 0 {
                let step = (at(j, '/') && at(j + 1, '*'), at(j, '*') && at(j + 1, '/'));
                depth = depth + usize::from(step.0) - usize::from(step.1);
                j += if step.0 || step.1 { 2 } else { 1 };
            }
            j
        } else if raw > 0 && !ident_before && at(raw + hashes, '"') {
            let mut j = raw + hashes + 1;
            while j < c.len() && !(at(j, '"') && (1..=hashes).all(|k| at(j + k, '#'))) {
                j += 1;
            }
            j + 1 + hashes
        } else if at(i, '"') || (at(i, '\'') && (at(i + 1, '\\') || at(i + 2, '\''))) {
            let mut j = i + 1;
            while j < c.len() && c[j] != c[i] {
                j += if c[j] == '\\' { 2 } else { 1 };
            }
            j + 1
        } else {
            out.push(c[i]);
            i += 1;
            continue;
        };
        let end = end.min(c.len());
        out.extend(
            c[i..end]
                .iter()
                .map(|&ch| if ch == '\n' { '\n' } else { ' ' }),
        );
        i = end;
    }
    out.into_iter().collect()
}

/// Identifiers, `::` and single punctuation characters.
fn tokens(code: &str) -> Vec<String> {
    let c: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < c.len() {
        if c[i].is_alphabetic() || c[i] == '_' {
            let s = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push(c[s..i].iter().collect());
        } else if c[i].is_numeric() {
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_' || c[i] == '.') {
                i += 1;
            }
        } else if c[i] == ':' && c.get(i + 1) == Some(&':') {
            out.push("::".into());
            i += 2;
        } else {
            if !c[i].is_whitespace() {
                out.push(c[i].to_string());
            }
            i += 1;
        }
    }
    out
}

fn is_ident(t: &str) -> bool {
    t.chars()
        .next()
        .is_some_and(|ch| ch.is_alphabetic() || ch == '_')
}

/// Flattens a use tree starting at `toks[*i]` (after `use`) into leaves, up to `;` or `,`/`}`.
fn use_tree(
    toks: &[String],
    i: &mut usize,
    prefix: &[String],
    out: &mut Vec<UseDecl>,
    public: bool,
) {
    let mut path = prefix.to_vec();
    let (mut named, mut glob, mut alias) = (false, false, None);
    while *i < toks.len() {
        match toks[*i].as_str() {
            "{" => {
                *i += 1;
                while *i < toks.len() && toks[*i] != "}" {
                    use_tree(toks, i, &path, out, public);
                    *i += usize::from(toks.get(*i).is_some_and(|t| t == ","));
                }
                *i += 1;
                return;
            }
            "," | "}" | ";" => break,
            "*" => (named, glob) = (true, true),
            "self" if !path.is_empty() => named = true,
            "as" => {
                *i += 1;
                alias = toks.get(*i).cloned();
            }
            t if is_ident(t) => {
                path.push(t.to_string());
                named = true;
            }
            _ => {}
        }
        *i += 1;
    }
    if named {
        let last = if glob {
            "*".to_string()
        } else {
            path.last().cloned().unwrap_or_default()
        };
        let local = alias.unwrap_or(last);
        out.push(UseDecl {
            local,
            path,
            glob,
            public,
        });
    }
}

struct Crate {
    modules: BTreeMap<ModPath, Module>,
    refs: Vec<Ref>,
    /// Modules under `#[cfg(test)]`: leaves nothing imports, so their paths cannot close a
    /// cycle and are not read.
    tests: BTreeSet<ModPath>,
    /// Per file: identifiers used outside `use` declarations.
    idents: BTreeMap<PathBuf, BTreeSet<String>>,
}

impl Crate {
    fn read(&mut self, root: &ModPath, file: &Path) {
        let src = fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let toks = tokens(&strip(&src));
        let dir = match file.file_name().and_then(|n| n.to_str()) {
            Some("mod.rs" | "lib.rs" | "main.rs") => file.parent().unwrap().to_path_buf(),
            _ => file.with_extension(""),
        };
        let mut stack: Vec<(ModPath, usize)> = vec![(root.clone(), 0)];
        let mut depth = 0;
        let mut idents = BTreeSet::new();
        let mut children = Vec::new();
        self.modules.entry(root.clone()).or_default().file = file.to_path_buf();
        let mut i = 0;
        while i < toks.len() {
            let here = stack.last().unwrap().0.clone();
            let t = toks[i].as_str();
            let public = i > 0
                && (toks[i - 1] == "pub" || (toks[i - 1] == ")" && i >= 4 && toks[i - 4] == "pub"));
            if t == "{" {
                depth += 1;
            } else if t == "}" {
                if stack.len() > 1 && stack.last().unwrap().1 == depth {
                    stack.pop();
                }
                depth -= 1;
            } else if t == "mod" && i + 2 < toks.len() && is_ident(&toks[i + 1]) {
                let name = toks[i + 1].clone();
                let mut inner = here.clone();
                inner.push(name.clone());
                if i >= 7 && toks[i - 7..i].concat() == "#[cfg(test)]" {
                    self.tests.insert(inner.clone());
                }
                self.modules
                    .entry(here.clone())
                    .or_default()
                    .children
                    .insert(name.clone());
                if toks[i + 2] == ";" && stack.len() == 1 {
                    children.push((inner, name));
                } else if toks[i + 2] == "{" {
                    self.modules.entry(inner.clone()).or_default().file = file.to_path_buf();
                    depth += 1;
                    stack.push((inner, depth));
                    i += 3;
                    continue;
                }
                i += 2;
                continue;
            } else if t == "use" && (i == 0 || toks[i - 1] != "::") {
                i += 1;
                let mut leaves = Vec::new();
                use_tree(&toks, &mut i, &[], &mut leaves, public);
                for u in leaves {
                    self.refs.push(Ref {
                        module: here.clone(),
                        path: u.path.clone(),
                        from_use: Some(u.clone()),
                    });
                    self.modules.entry(here.clone()).or_default().uses.push(u);
                }
                continue;
            } else if is_ident(t)
                && toks.get(i + 1).is_some_and(|n| n == "::")
                && (i == 0 || toks[i - 1] != "::")
            {
                let mut path = vec![t.to_string()];
                let mut j = i + 1;
                while j + 1 < toks.len() && toks[j] == "::" && is_ident(&toks[j + 1]) {
                    path.push(toks[j + 1].clone());
                    j += 2;
                }
                idents.insert(t.to_string());
                self.refs.push(Ref {
                    module: here,
                    path,
                    from_use: None,
                });
                i = j;
                continue;
            } else if is_ident(t) {
                idents.insert(t.to_string());
            }
            i += 1;
        }
        self.idents.insert(file.to_path_buf(), idents);
        for (inner, name) in children {
            let a = dir.join(format!("{name}.rs"));
            let b = dir.join(&name).join("mod.rs");
            let f = if a.exists() { a } else { b };
            if f.exists() {
                self.read(&inner, &f);
            }
        }
    }

    fn file(&self, m: &ModPath) -> Option<PathBuf> {
        self.modules.get(m).map(|m| m.file.clone())
    }

    /// The module a path written in `m` starts from, and the rest of the path.
    fn start(
        &self,
        m: &ModPath,
        path: &[String],
        depth: usize,
    ) -> Option<(ModPath, Vec<String>, bool)> {
        let first = path.first()?.as_str();
        let rest = path[1..].to_vec();
        let root = vec![m[0].clone()];
        match first {
            "crate" => Some((root, rest, true)),
            "qjulia" => Some((vec!["lib".into()], rest, true)),
            "self" => Some((m.clone(), rest, true)),
            "super" => {
                let mut up = m[..m.len() - 1].to_vec();
                let mut rest = rest;
                while rest.first().is_some_and(|s| s == "super") {
                    up.pop();
                    rest.remove(0);
                }
                Some((up, rest, true))
            }
            _ => {
                let module = self.modules.get(m)?;
                if module.children.contains(first) {
                    return Some((m.clone(), path.to_vec(), true));
                }
                let u = module.uses.iter().find(|u| !u.glob && u.local == first)?;
                let (t, is_mod) = self.resolve(m, &u.path, depth + 1)?;
                let mut rest = rest;
                if is_mod {
                    Some((t, rest, true))
                } else {
                    rest.clear();
                    Some((t, rest, false))
                }
            }
        }
    }

    /// Resolves a path written in module `m`: the defining module, and whether the path names
    /// that module itself (rather than an item in it).
    fn resolve(&self, m: &ModPath, path: &[String], depth: usize) -> Option<(ModPath, bool)> {
        if depth > 32 {
            return None;
        }
        let (mut at, rest, is_mod) = self.start(m, path, depth)?;
        if !is_mod {
            return Some((at, false));
        }
        for (k, seg) in rest.iter().enumerate() {
            let module = self.modules.get(&at)?;
            if module.children.contains(seg) {
                at.push(seg.clone());
                continue;
            }
            if let Some(u) = module.uses.iter().find(|u| !u.glob && &u.local == seg) {
                let mut through = u.path.clone();
                through.extend(rest[k + 1..].iter().cloned());
                return self.resolve(&at, &through, depth + 1);
            }
            return Some((at, false));
        }
        Some((at, true))
    }
}

fn main_graph() -> (Graph, usize) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut krate = Crate {
        modules: BTreeMap::new(),
        refs: Vec::new(),
        tests: BTreeSet::new(),
        idents: BTreeMap::new(),
    };
    krate.read(&vec!["lib".into()], &root.join("src/lib.rs"));
    krate.read(&vec!["bin".into()], &root.join("src/main.rs"));
    let name = |p: &Path| p.strip_prefix(&root).unwrap_or(p).display().to_string();
    let mut graph: Graph = BTreeMap::new();
    for r in &krate.refs {
        if (1..=r.module.len()).any(|n| krate.tests.contains(&r.module[..n])) {
            continue;
        }
        let Some(from) = krate.file(&r.module) else {
            continue;
        };
        if let Some(u) = &r.from_use
            && u.public
            && !krate.idents[&from].contains(&u.local)
        {
            continue;
        }
        let Some((target, is_mod)) = krate.resolve(&r.module, &r.path, 0) else {
            continue;
        };
        if is_mod && r.from_use.as_ref().is_some_and(|u| !u.glob) {
            continue;
        }
        let Some(to) = krate.file(&target) else {
            continue;
        };
        let (from, to) = (name(&from), name(&to));
        if from == to {
            continue;
        }
        graph
            .entry(from)
            .or_default()
            .entry(to)
            .or_insert_with(|| r.path.join("::"));
    }
    (graph, krate.modules.len())
}

/// The strongly connected components of more than one file: the knots the cycles run through.
fn knots(graph: &Graph) -> Vec<Vec<String>> {
    let mut out: Vec<Vec<String>> = Vec::new();
    for v in graph.keys() {
        if out.iter().any(|k| k.contains(v)) {
            continue;
        }
        let knot: Vec<String> = graph
            .keys()
            .filter(|w| *w == v || (reaches(graph, v, w) && reaches(graph, w, v)))
            .cloned()
            .collect();
        if knot.len() > 1 {
            out.push(knot);
        }
    }
    out
}

/// Whether a path of edges leads from `from` to `to`.
fn reaches(graph: &Graph, from: &str, to: &str) -> bool {
    let mut seen = BTreeSet::from([from]);
    let mut todo = vec![from];
    while let Some(v) = todo.pop() {
        for w in graph.get(v).into_iter().flat_map(|m| m.keys()) {
            if w == to {
                return true;
            }
            if seen.insert(w.as_str()) {
                todo.push(w.as_str());
            }
        }
    }
    false
}

/// The shortest cycle through `start` inside one knot.
fn cycle_through(graph: &Graph, knot: &BTreeSet<&str>, start: &str) -> Vec<String> {
    let mut prev: BTreeMap<&str, &str> = BTreeMap::new();
    let mut queue = VecDeque::from([start]);
    while let Some(v) = queue.pop_front() {
        for w in graph.get(v).into_iter().flat_map(|m| m.keys()) {
            let w = w.as_str();
            if !knot.contains(w) {
                continue;
            }
            if w == start {
                let mut chain = vec![start.to_string(), v.to_string()];
                let mut at = v;
                while at != start {
                    at = prev[at];
                    chain.push(at.to_string());
                }
                chain.reverse();
                return chain;
            }
            if !prev.contains_key(w) && w != start {
                prev.insert(w, v);
                queue.push_back(w);
            }
        }
    }
    Vec::new()
}

#[test]
fn no_import_cycles() {
    let (mut graph, modules) = main_graph();
    assert!(
        modules > 20 && graph.len() > 20,
        "the scan found too little: {modules} modules"
    );
    let mut stale = Vec::new();
    for &entry in ALLOWED {
        let (from, to) = allowed(entry);
        if graph.get_mut(from).and_then(|m| m.remove(to)).is_none() {
            stale.push(format!("{from} -> {to}: no such edge"));
        }
    }
    for &entry in ALLOWED {
        let (from, to) = allowed(entry);
        if !reaches(&graph, to, from) {
            stale.push(format!("{from} -> {to}: no cycle runs through it"));
        }
    }
    assert!(
        stale.is_empty(),
        "ALLOWED lists edges no longer needed:\n{}",
        stale.join("\n")
    );
    let knots = knots(&graph);
    let mut report = String::new();
    for knot in &knots {
        report += &format!("\na knot of {} files: {}\n", knot.len(), knot.join(", "));
        let set: BTreeSet<&str> = knot.iter().map(|s| s.as_str()).collect();
        let mut seen = BTreeSet::new();
        for start in knot {
            let chain = cycle_through(&graph, &set, start);
            let mut key: Vec<String> = chain[1..].to_vec();
            key.sort();
            if chain.is_empty() || !seen.insert(key) {
                continue;
            }
            report += &format!("  cycle: {}\n", chain.join(" -> "));
            for pair in chain.windows(2) {
                report += &format!(
                    "    {} -> {}: {}\n",
                    pair[0], pair[1], graph[&pair[0]][&pair[1]]
                );
            }
        }
    }
    assert!(
        knots.is_empty(),
        "import cycles between the crate's files:{report}"
    );
}

/// The scanner itself, on a tree that is known: grouped uses, re-exports, `super`, comments.
#[test]
fn the_scanner_reads_what_it_should() {
    let code =
        strip("let s = \"crate::x\"; // crate::y\n/* crate::z */ let c = '\"'; r#\"a\"#; crate::w");
    assert_eq!(
        tokens(&code),
        [
            "let", "s", "=", ";", "let", "c", "=", ";", ";", "crate", "::", "w"
        ]
    );
    let toks = tokens("crate::{a, b::{c, d as e}, f::*, g::{self}};");
    let mut out = Vec::new();
    use_tree(&toks, &mut 0, &[], &mut out, false);
    let got: Vec<(String, String)> = out
        .iter()
        .map(|u| (u.local.clone(), u.path.join("::")))
        .collect();
    let want = [
        ("a", "crate::a"),
        ("c", "crate::b::c"),
        ("e", "crate::b::d"),
        ("*", "crate::f"),
        ("g", "crate::g"),
    ];
    assert_eq!(got, want.map(|(a, b)| (a.to_string(), b.to_string())));
}
