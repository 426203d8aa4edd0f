//! The WGSL composer: each file of shaders/ names what it needs with `#import` lines and gates
//! its own text with `#if`, and a kernel is its root file composed for a set of features,
//! before any WGSL parser sees it.
//!
//! The rules (docs/CONTRACT.md, "Kernels"; web/src/compose.ts is the twin, held to this byte
//! for byte by web/test/fixtures/kernels.json):
//!
//! - A directive is a line whose first character is `#`: `#import NAME` (the file
//!   shaders/NAME.wgsl), `#if FEATURE`, `#if !FEATURE`, `#else` and `#endif`. Conditions nest; a
//!   line counts where every condition around it holds. A feature must be declared in
//!   shaders/kernels.json, so that a misspelt one is an error rather than a branch never taken.
//! - Composing a file composes, in their order, the files its counted `#import` lines name, then
//!   appends its own counted lines that are not directives. A file already composed into the
//!   kernel is not composed again, and a file that imports itself, directly or not, is an error.
//! - Each file's lines are its text split at `\n`; the kernel is the files' kept lines joined
//!   with `\n`, file after file joined with `\n` (the join the hand-kept lists used before).

use std::collections::BTreeSet;

/// Why a kernel cannot be composed: one line naming the file and its line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct ComposeError(pub String);

/// The files a kernel can be composed from, by name (a file's stem), and the features it may
/// test.
pub struct Composer<'a> {
    files: &'a dyn Fn(&str) -> Option<&'a str>,
    features: &'a [&'a str],
}

/// A composed kernel: its text and the files it holds, in the order they were appended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Composed {
    pub text: String,
    pub files: Vec<String>,
}

/// One file's lines after its conditions are evaluated: what it imports and what it keeps.
struct Evaluated<'t> {
    imports: Vec<&'t str>,
    kept: Vec<&'t str>,
}

impl<'a> Composer<'a> {
    /// A composer over `files` (a name to its text, `None` where no such file is), whose
    /// directives may test `features` (the declared set).
    pub fn new(files: &'a dyn Fn(&str) -> Option<&'a str>, features: &'a [&'a str]) -> Self {
        Self { files, features }
    }

    /// The kernel rooted at `root` with the features `on` (each one declared) turned on.
    pub fn compose(&self, root: &str, on: &[&str]) -> Result<Composed, ComposeError> {
        if let Some(f) = on.iter().find(|f| !self.features.contains(f)) {
            return Err(ComposeError(format!("unknown feature `{f}`")));
        }
        let mut state = State {
            done: Vec::new(),
            open: Vec::new(),
            parts: Vec::new(),
        };
        self.visit(root, on, None, &mut state)?;
        Ok(Composed {
            text: state.parts.join("\n"),
            files: state.done,
        })
    }

    fn visit(
        &self,
        name: &str,
        on: &[&str],
        from: Option<&str>,
        state: &mut State,
    ) -> Result<(), ComposeError> {
        if state.done.iter().any(|d| d == name) {
            return Ok(());
        }
        if state.open.iter().any(|o| o == name) {
            let first = state.open.iter().position(|o| o == name).unwrap_or(0);
            let chain = state.open[first..].join(" -> ");
            return Err(ComposeError(format!(
                "shaders/{name}.wgsl imports itself: {chain} -> {name}"
            )));
        }
        let Some(text) = (self.files)(name) else {
            let by = from.map_or(String::new(), |f| format!(" (imported by {f})"));
            return Err(ComposeError(format!(
                "no shader file shaders/{name}.wgsl{by}"
            )));
        };
        state.open.push(name.to_string());
        let evaluated = self.evaluate(name, text, on)?;
        let at = format!("shaders/{name}.wgsl");
        for import in evaluated.imports {
            self.visit(import, on, Some(&at), state)?;
        }
        state.open.pop();
        state.done.push(name.to_string());
        state.parts.push(evaluated.kept.join("\n"));
        Ok(())
    }

    /// `text`'s lines with its conditions evaluated for `on`: the imports counted and the other
    /// lines kept.
    fn evaluate<'t>(
        &self,
        name: &str,
        text: &'t str,
        on: &[&str],
    ) -> Result<Evaluated<'t>, ComposeError> {
        let fail = |line: usize, what: String| {
            Err(ComposeError(format!(
                "shaders/{name}.wgsl:{}: {what}",
                line + 1
            )))
        };
        // Each open `#if`: whether its branch now counts, and whether an `#else` was seen.
        let mut conditions: Vec<(bool, bool)> = Vec::new();
        let mut out = Evaluated {
            imports: Vec::new(),
            kept: Vec::new(),
        };
        for (n, line) in text.split('\n').enumerate() {
            let counts = conditions.iter().all(|c| c.0);
            let Some(directive) = line.strip_prefix('#') else {
                if counts {
                    out.kept.push(line);
                }
                continue;
            };
            let words: Vec<&str> = directive.split_whitespace().collect();
            match words.as_slice() {
                ["import", module] => {
                    if counts {
                        out.imports.push(module);
                    }
                }
                ["if", feature] => {
                    let (negated, feature) = match feature.strip_prefix('!') {
                        Some(f) => (true, f),
                        None => (false, *feature),
                    };
                    if !self.features.contains(&feature) {
                        return fail(n, format!("unknown feature `{feature}`"));
                    }
                    conditions.push((on.contains(&feature) != negated, false));
                }
                ["else"] => match conditions.last_mut() {
                    Some((holds, seen)) if !*seen => {
                        *holds = !*holds;
                        *seen = true;
                    }
                    Some(_) => return fail(n, "a second `#else`".into()),
                    None => return fail(n, "`#else` without `#if`".into()),
                },
                ["endif"] => {
                    if conditions.pop().is_none() {
                        return fail(n, "`#endif` without `#if`".into());
                    }
                }
                _ => return fail(n, format!("unknown directive `{}`", line.trim_end())),
            }
        }
        if !conditions.is_empty() {
            return fail(
                text.split('\n').count() - 1,
                "`#if` without `#endif`".into(),
            );
        }
        Ok(out)
    }
}

/// The files composed so far, those being composed (the chain of imports), and the text.
struct State {
    done: Vec<String>,
    open: Vec<String>,
    parts: Vec<String>,
}

/// The features a set of files tests, sorted (the declared set must hold them all).
pub fn features_tested<'t>(texts: impl IntoIterator<Item = &'t str>) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for text in texts {
        for line in text.split('\n') {
            if let Some(f) = line.strip_prefix("#if ") {
                found.insert(f.trim().trim_start_matches('!').to_string());
            }
        }
    }
    found
}

/// The 64-bit FNV-1a hash of `bytes`, as 16 lowercase hex digits: a kernel's fingerprint in
/// `--stats` and `qjulia kernel` (web/src/compose.ts has the twin).
pub fn fingerprint(bytes: &[u8]) -> String {
    format!("{:016x}", fnv1a(bytes))
}

/// The 64-bit FNV-1a hash of `bytes` (the `fnv` crate's).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    use std::hash::Hasher as _;
    let mut h = fnv::FnvHasher::default();
    h.write(bytes);
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn compose(files: &[(&'static str, &'static str)], root: &str, on: &[&str]) -> String {
        let lookup = |n: &str| files.iter().find(|f| f.0 == n).map(|f| f.1);
        let composer = Composer::new(&lookup, &["A", "B"]);
        match composer.compose(root, on) {
            Ok(c) => c.text,
            Err(e) => format!("error: {e}"),
        }
    }

    #[test]
    fn imports_come_first_and_once() {
        let files = [
            ("main", "#import b\n#import a\nmain\n"),
            ("a", "#import b\na\n"),
            ("b", "b"),
        ];
        assert_eq!(compose(&files, "main", &[]), "b\na\n\nmain\n");
    }

    #[test]
    fn conditions_choose_lines_and_imports() {
        let files = [
            (
                "main",
                "#if A\n#import a\none\n#else\ntwo\n#endif\n#if !B\nthree\n#endif",
            ),
            ("a", "a"),
        ];
        assert_eq!(compose(&files, "main", &["A"]), "a\none\nthree");
        assert_eq!(compose(&files, "main", &["B"]), "two");
        assert_eq!(compose(&files, "main", &["A", "B"]), "a\none");
    }

    #[test]
    fn nested_conditions_need_every_one() {
        let files = [("main", "#if A\n#if B\nab\n#else\na\n#endif\n#endif\nend")];
        assert_eq!(compose(&files, "main", &["A", "B"]), "ab\nend");
        assert_eq!(compose(&files, "main", &["A"]), "a\nend");
        assert_eq!(compose(&files, "main", &["B"]), "end");
    }

    #[test]
    fn errors_name_the_file_and_line() {
        let cases = [
            (
                ("main", "#import gone"),
                "error: no shader file shaders/gone.wgsl (imported by shaders/main.wgsl)",
            ),
            (
                ("main", "x\n#if C\n#endif"),
                "error: shaders/main.wgsl:2: unknown feature `C`",
            ),
            (
                ("main", "#if A\nx"),
                "error: shaders/main.wgsl:2: `#if` without `#endif`",
            ),
            (
                ("main", "#endif"),
                "error: shaders/main.wgsl:1: `#endif` without `#if`",
            ),
            (
                ("main", "#if A\n#else\n#else\n#endif"),
                "error: shaders/main.wgsl:3: a second `#else`",
            ),
            (
                ("main", "#include x"),
                "error: shaders/main.wgsl:1: unknown directive `#include x`",
            ),
        ];
        for ((name, text), message) in cases {
            assert_eq!(compose(&[(name, text)], "main", &[]), message);
        }
        let cycle = [("main", "#import a"), ("a", "#import main")];
        assert_eq!(
            compose(&cycle, "main", &[]),
            "error: shaders/main.wgsl imports itself: main -> a -> main"
        );
        assert_eq!(
            compose(&[("main", "")], "main", &["Z"]),
            "error: unknown feature `Z`"
        );
    }

    #[test]
    fn fingerprint_is_fnv1a_64() {
        // The published FNV-1a test vectors.
        assert_eq!(fingerprint(b""), "cbf29ce484222325");
        assert_eq!(fingerprint(b"a"), "af63dc4c8601ec8c");
        assert_eq!(fingerprint(b"foobar"), "85944171f73967e8");
    }
}
