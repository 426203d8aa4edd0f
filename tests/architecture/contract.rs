//! docs/CONTRACT.md held to the code: every key of its ```` ```toml ```` blocks is a key of the
//! scene schema (src/scene/mod.rs) with the schema's default, its `range:` the schema's range
//! and, for a choice, its comment quoting exactly the choice's names; every key of the schema is
//! in the contract; the `[animation]` block loads with the animation loader, and states its
//! keys, defaults and ranges; every command and flag of the usage block is the binary's; the
//! exit codes it names (0, 1, 2) are the binary's, its example errors word for word. Each
//! failure says what to change in docs/CONTRACT.md.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::{Command, Output};

use qjulia::Scene;
use qjulia::animation::{Animation, FRAMES_MAX, FRAMES_MIN};
use qjulia::scene::schema::json::SchemaJson;
use qjulia::scene::schema::{self, Kind, SCHEMA, TABLES};
use qjulia::scene::{SceneLoader, SceneSource};
use toml::Value;

const CONTRACT: &str = "docs/CONTRACT.md";

fn contract() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(CONTRACT);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{CONTRACT} is readable: {e}"))
}

/// A fenced block of the contract: its language (`toml`, or "" for none), the line number of
/// its first line of text, and that text.
struct Block {
    lang: String,
    line: usize,
    text: String,
}

fn blocks(text: &str) -> Vec<Block> {
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    for (i, line) in text.lines().enumerate() {
        match (open.as_mut(), line.strip_prefix("```")) {
            (None, Some(lang)) => {
                let (lang, line, text) = (lang.trim().to_string(), i + 2, String::new());
                open = Some(Block { lang, line, text });
            }
            (Some(_), Some(_)) => out.extend(open.take()),
            (Some(block), None) => block.text.push_str(&format!("{line}\n")),
            (None, None) => {}
        }
    }
    assert!(open.is_none(), "{CONTRACT}: a ``` block is not closed");
    out
}

/// The ```` ```toml ```` blocks, each parsed apart (a table may appear in several).
fn toml_blocks(text: &str) -> Vec<(Block, toml::Table)> {
    let parse = |b: Block| match b.text.parse::<toml::Table>() {
        Ok(table) => (b, table),
        Err(e) => panic!(
            "{CONTRACT}: the ```toml block at line {} is not TOML (write each key's real \
             default, not a placeholder such as [...]):\n{e}",
            b.line
        ),
    };
    let toml = blocks(text).into_iter().filter(|b| b.lang == "toml");
    toml.map(parse).collect()
}

/// One `key = value  # comment` line of a TOML block: its dotted path (the table's name, then
/// the key), its line in the contract, its value and its comment (with the comment lines that
/// continue it).
struct Entry {
    path: String,
    line: usize,
    value: Value,
    comment: String,
}

/// Every key line of `block`, in order; keys under `[animation]` and `[[animation.keys]]` too.
fn entries(block: &Block, parsed: &toml::Table) -> Vec<Entry> {
    let mut out: Vec<Entry> = Vec::new();
    let mut table = String::new();
    // Whether a comment line continues the last entry's comment.
    let mut continues = false;
    for (i, line) in block.text.lines().enumerate() {
        let (code, comment) = split_comment(line);
        let (code, line, at) = (code.trim(), line, block.line + i);
        if code.is_empty() {
            match (out.last_mut(), comment) {
                (Some(last), Some(more)) if continues && line.starts_with(' ') => {
                    last.comment = format!("{} {}", last.comment, more.trim());
                }
                _ => continues = false,
            }
        } else if let Some(name) = code.strip_prefix('[') {
            table = name.trim_matches(|c| c == '[' || c == ']').to_string();
            continues = false;
        } else {
            let (key, _) = code.split_once('=').unwrap_or_else(|| {
                panic!("{CONTRACT}:{at}: not `key = value`");
            });
            let path = format!("{table}.{}", key.trim());
            let value = lookup(parsed, &path).unwrap_or_else(|| {
                panic!("{CONTRACT}:{at}: one `key = value` a line, please");
            });
            let comment = comment.unwrap_or_default().trim().to_string();
            out.push(Entry {
                path,
                line: at,
                value,
                comment,
            });
            continues = true;
        }
    }
    out
}

/// `line` split at its comment's `#` (one outside a string).
fn split_comment(line: &str) -> (&str, Option<&str>) {
    let mut quoted = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => quoted = !quoted,
            '#' if !quoted => return (&line[..i], Some(&line[i + 1..])),
            _ => {}
        }
    }
    (line, None)
}

/// The value at dotted `path` in `table` (in an array of tables, its last table).
fn lookup(table: &toml::Table, path: &str) -> Option<Value> {
    let mut value = Value::Table(table.clone());
    for part in path.split('.') {
        if let Value::Array(items) = value {
            value = items.last()?.clone();
        }
        value = value.as_table()?.get(part)?.clone();
    }
    Some(value)
}

/// Every key line of every TOML block.
fn all_entries() -> Vec<Entry> {
    let blocks = toml_blocks(&contract());
    blocks.iter().flat_map(|(b, t)| entries(b, t)).collect()
}

/// The schema's range of `kind` as the contract writes it after `range:`: `1..4096`, `> 0`,
/// `>= 0`, `(0, 180)`, `[0, 1]`, `each >= 0` (the book's `range_text`, its `in ` dropped and
/// its `components` written `each`); None where the key has no range beyond its type.
fn schema_range(kind: &Kind) -> Option<String> {
    let text = kind.range_text()?;
    Some(text.replace("components ", "each ").replace("in ", ""))
}

/// Whether a comment states `range: {want}` (then its end, or its prose after a space or
/// `;`, `,`, `.`, `:`), and no other `range:`.
fn states_range(comment: &str, want: &str) -> bool {
    let stated = comment.split_once("range:").map(|(_, r)| r.trim_start());
    let rest = stated.and_then(|s| s.strip_prefix(want));
    let ends = rest.is_some_and(|r| r.is_empty() || r.starts_with([' ', ';', ',', '.', ':']));
    ends && comment.matches("range:").count() == 1
}

/// Whether a value of the contract is `default` (an integer where a float is, too).
fn same_value(contract: &Value, default: &Value) -> bool {
    match (contract, default) {
        (Value::Array(a), Value::Array(b)) => {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same_value(x, y))
        }
        (Value::Integer(i), Value::Float(x)) => *i as f64 == *x,
        _ => contract == default,
    }
}

/// Fails listing `failures`, one line each, with what to change in the contract.
fn report(failures: Vec<String>, what: &str) {
    let message = format!("{CONTRACT} and {what} disagree");
    assert!(failures.is_empty(), "{message}:\n{}", failures.join("\n"));
}

/// The scene file's text `text` and `--set`s through the loader: the scene and animation.
fn load(text: &str, sets: &[&str]) -> Result<(Scene, Animation), String> {
    let mut loader = SceneLoader::new();
    let source = SceneSource::File(CONTRACT.into());
    let mut layers = loader.toml_str(text, source);
    for set in sets {
        layers = layers.and_then(|()| loader.set(set));
    }
    layers
        .and_then(|()| loader.build_animated())
        .map_err(|e| e.to_string())
}

const SCHEMA_FILE: &str = "the scene schema (src/scene/mod.rs)";

#[test]
fn ranges_read_as_the_contract_writes_them() {
    let range = |path| schema_range(&schema::key(path).expect(path).kind).unwrap_or_default();
    assert_eq!(range("image.samples"), "1..4096");
    assert_eq!(range("fractal.step_scale"), "(0, 2]");
    assert_eq!(range("shading.diffuse"), "each [0, 1]");
    assert!(states_range("rays; range: 1..4096. Sample 0", "1..4096"));
    assert!(states_range("range: [0, 1] (alpha = ...)", "[0, 1]"));
    assert!(!states_range("range: 1..40960", "1..4096"));
    assert!(!states_range("range: >= 0; range: >= 0", ">= 0"));
}

/// Every key of the contract's blocks (but `[animation]`'s) is a scene key with its default,
/// its range and its choices; each block loads as a scene file.
#[test]
fn every_contract_key_is_the_schemas_with_its_default_and_range() {
    let defaults = Scene::default();
    let mut failures = Vec::new();
    for (block, _) in toml_blocks(&contract()) {
        if let Err(e) = load(&block.text, &[]) {
            let at = block.line;
            failures.push(format!("the block at line {at} does not load: {e}"));
        }
    }
    let tables: Vec<&str> = TABLES.iter().map(|t| t.name).collect();
    for entry in all_entries() {
        let (path, line, comment) = (&entry.path, entry.line, &entry.comment);
        let table = path.split('.').next().unwrap_or("");
        if table == "animation" {
            continue;
        }
        let Some(key) = schema::key(path) else {
            failures.push(match tables.contains(&table) {
                true => format!("line {line}: {path} is no key of the schema: remove it"),
                false => format!("line {line}: [{table}] is no table of the schema: remove it"),
            });
            continue;
        };
        let (value, default) = (&entry.value, key.kind.value(&defaults));
        if !same_value(value, &default) {
            let leaf = key.leaf();
            failures.push(format!(
                "line {line}: {path} = {value} but its default is {default}: write \
                 `{leaf} = {default}`"
            ));
        }
        let stated = comment.split_once("range:");
        let stated = stated.map(|(_, r)| r.split(';').next().unwrap_or("").trim());
        match schema_range(&key.kind) {
            Some(want) if !states_range(comment, &want) => failures.push(format!(
                "line {line}: {path}'s range is {want}, its comment states {:?}: write \
                 `range: {want}` in its comment (once)",
                stated.unwrap_or("none")
            )),
            None if stated.is_some() => failures.push(format!(
                "line {line}: {path} has no range in the schema (any finite number): remove \
                 its `range:`"
            )),
            _ => {}
        }
        if let Kind::Choice { names, .. } = key.kind {
            let names: BTreeSet<String> = names().into_iter().map(String::from).collect();
            // The strings the comment quotes.
            let quotes = comment.split('"').skip(1).step_by(2);
            let quotes: BTreeSet<String> = quotes.map(Into::into).collect();
            if quotes != names {
                failures.push(format!(
                    "line {line}: {path}'s comment quotes {quotes:?}; its choices are \
                     {names:?}: quote each of them, and nothing else"
                ));
            }
        }
    }
    report(failures, SCHEMA_FILE);
}

/// Every key of the schema is in one of the contract's blocks.
#[test]
fn every_schema_key_is_in_the_contract() {
    let listed: BTreeSet<String> = all_entries().into_iter().map(|e| e.path).collect();
    let defaults = Scene::default();
    let missing = SCHEMA.iter().filter(|k| !listed.contains(k.path)).map(|k| {
        // The book's comment, its range written as `range:`.
        let mut comment = k.readme.to_string();
        for range in [" ({range})", ", finite and {range}", ", {range}", "{range}"] {
            comment = comment.replace(range, "");
        }
        if let Some(range) = schema_range(&k.kind) {
            comment = format!("{comment}; range: {range}");
        }
        let (path, leaf, value, table) = (k.path, k.leaf(), k.kind.value(&defaults), k.table());
        format!("{path} is missing: add `{leaf} = {value}  # {comment}` to a [{table}]")
    });
    report(missing.collect(), SCHEMA_FILE);
}

/// The `[animation]` block loads with the animation loader, and states each of the loader's
/// keys with its default and its range.
#[test]
fn the_animation_block_is_the_animation_loaders() {
    let text = contract();
    let blocks = toml_blocks(&text);
    let Some((block, parsed)) = blocks.iter().find(|(_, t)| t.contains_key("animation")) else {
        panic!("{CONTRACT} has no ```toml block with [animation]");
    };
    let at = block.line;
    if let Err(e) = load(&block.text, &[]) {
        panic!("{CONTRACT}'s [animation] block (line {at}) does not load: {e}");
    }
    let mut failures = Vec::new();
    // The loader's keys and defaults, as it writes them.
    let written: toml::Table = Animation::default().to_toml().parse().expect("TOML");
    let defaults = written["animation"].as_table().expect("[animation]");
    let stated = parsed["animation"].as_table().expect("a table");
    for (name, default) in defaults {
        match stated.get(name) {
            None => failures.push(format!(
                "[animation] lacks {name}: add `{name} = {default}`"
            )),
            Some(v) if !same_value(v, default) => failures.push(format!(
                "animation.{name} = {v} but the loader's default is {default}: write that"
            )),
            Some(_) => {}
        }
    }
    // The loader's ranges (src/scene/load/animation.rs), each probed at its ends: a value,
    // and whether the loader takes it.
    let frames = format!("{FRAMES_MIN}..{FRAMES_MAX}");
    let (min, max) = (f64::from(FRAMES_MIN), f64::from(FRAMES_MAX));
    let ranges = [
        ("frames", frames.as_str()),
        ("fps", "> 0"),
        ("path_radius", ">= 0"),
    ];
    let probes = [
        ("frames", min, true),
        ("frames", min - 1.0, false),
        ("frames", max, true),
        ("frames", max + 1.0, false),
        ("fps", 0.0, false),
        ("fps", 1e-9, true),
        ("path_radius", 0.0, true),
        ("path_radius", -1e-9, false),
    ];
    for (name, value, takes) in probes {
        let set = format!("animation.{name}={value}");
        if load("", &[&set]).is_ok() != takes {
            failures.push(format!(
                "the loader no longer holds animation.{name} to its range (--set {set}): update \
                 this test and {CONTRACT}"
            ));
        }
    }
    for entry in entries(block, parsed) {
        let (path, line) = (&entry.path, entry.line);
        let Some(name) = path.strip_prefix("animation.") else {
            continue;
        };
        match ranges.iter().find(|(n, _)| *n == name) {
            Some((_, range)) if !states_range(&entry.comment, range) => failures.push(format!(
                "line {line}: {path} is in {range}: write `range: {range}` in its comment"
            )),
            None if !name.starts_with("keys.") => failures.push(format!(
                "line {line}: {path} is no key this test knows the range of: add it to `ranges`"
            )),
            _ => {}
        }
    }
    report(
        failures,
        "the animation loader (src/scene/load/animation.rs)",
    );
}

/// Runs the binary in `dir` with no display (so that `qjulia` alone prints help).
fn qjulia(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_qjulia"));
    command
        .args(args)
        .current_dir(dir)
        .envs(env.iter().copied());
    let command = command.env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY");
    command.output().expect("run qjulia")
}

fn utf8(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The flags of a usage text (`--name`, `-o`), each with the `a|b|c` names that follow it.
fn flags(usage: &str) -> Vec<(String, Vec<String>)> {
    let words: Vec<&str> = usage
        .split_whitespace()
        .map(|w| w.trim_matches(['[', ']']))
        .collect();
    let plain = |s: &str| {
        s.chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit())
    };
    let mut out = Vec::new();
    for (i, word) in words.iter().enumerate() {
        let name = word.trim_start_matches('-');
        let dashes = word.len() - name.len();
        if !(1..=2).contains(&dashes) || name.is_empty() {
            continue;
        }
        if !name.chars().all(|c| c.is_ascii_lowercase() || c == '-') {
            continue;
        }
        let next = words.get(i + 1).unwrap_or(&"");
        let names: Vec<String> = next.split('|').map(Into::into).collect();
        let choices = names.len() > 1 && names.iter().all(|n| plain(n));
        out.push((word.to_string(), if choices { names } else { Vec::new() }));
    }
    out
}

/// Whether a line of help starts a flag's paragraph (`-o, --output <FILE>`, `--json`), not a
/// list item (`- shaded: ...`).
fn flag_line(line: &str) -> bool {
    let mut chars = line.trim_start().chars();
    chars.next() == Some('-') && chars.next().is_some_and(|c| c == '-' || c.is_alphabetic())
}

/// Whether a line of help starts `flag`'s paragraph (`-o, --output <FILE.png>`, `--json`).
fn starts_flag(line: &str, flag: &str) -> bool {
    let mut parts = line.trim().split(", ").map(|p| p.split(' ').next());
    flag_line(line) && parts.any(|p| p == Some(flag))
}

/// Every command of the usage block answers `--help`, listing the flags (and the names of
/// their values) that the usage gives it; `qjulia` alone, without a display, prints help.
#[test]
fn every_command_and_flag_of_the_usage_is_the_binarys() {
    let text = contract();
    let usage = blocks(&text)
        .into_iter()
        .find(|b| b.text.starts_with("qjulia "));
    let usage = usage.expect("docs/CONTRACT.md has a usage block (``` `qjulia ...`)");
    let Some((commands, scene_options)) = usage.text.split_once("SCENE OPTIONS:") else {
        panic!("{CONTRACT}'s usage block has no SCENE OPTIONS:");
    };
    // Each command with its usage lines, comments dropped.
    let mut usages: Vec<(String, String)> = Vec::new();
    for line in commands.lines() {
        let code = line.split('#').next().unwrap_or("");
        if let Some(rest) = code.strip_prefix("qjulia ") {
            let name = rest.split_whitespace().next().unwrap_or("").to_string();
            usages.push((name, rest.to_string()));
        } else if let Some((_, usage)) = usages.last_mut() {
            usage.push_str(code);
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    for (name, usage) in &usages {
        if name.starts_with('(') {
            // No subcommand and no display: help on stdout, exit 0.
            let out = qjulia(dir.path(), &[], &[]);
            if out.status.code() != Some(0) || !utf8(&out.stdout).contains("Usage:") {
                failures.push(format!("`qjulia` alone without a display gives {out:?}"));
            }
            continue;
        }
        let out = qjulia(dir.path(), &[name, "--help"], &[]);
        if out.status.code() != Some(0) {
            failures.push(format!(
                "`qjulia {name}` is named but `qjulia {name} --help` gives {}: {}; remove it or \
                 name the command the binary has",
                out.status,
                utf8(&out.stderr).trim()
            ));
            continue;
        }
        let help = utf8(&out.stdout);
        let lines: Vec<&str> = help.lines().collect();
        let mut wanted = flags(usage);
        if usage.contains("[SCENE OPTIONS]") {
            wanted.extend(flags(scene_options));
        }
        for (flag, names) in wanted {
            let Some(start) = lines.iter().position(|l| starts_flag(l, &flag)) else {
                failures.push(format!(
                    "the usage gives `qjulia {name}` {flag}, which `qjulia {name} --help` does \
                     not list: remove it or name the flag the binary has"
                ));
                continue;
            };
            // The flag's paragraph of the help: from its line to the next flag's.
            let end = lines[start + 1..].iter().position(|l| flag_line(l));
            let paragraph = lines[start..end.map_or(lines.len(), |n| start + 1 + n)].join(" ");
            for value in names.iter().filter(|v| !paragraph.contains(v.as_str())) {
                failures.push(format!(
                    "the usage gives `qjulia {name} {flag} {value}`, which its help does not \
                     list:\n{paragraph}"
                ));
            }
        }
    }
    let commands = "render render2d animate mesh merge schema gpu-params report info explore";
    for wanted in commands.split(' ') {
        if !usages.iter().any(|(name, _)| name == wanted) {
            failures.push(format!("the usage block no longer names `qjulia {wanted}`"));
        }
    }
    report(failures, "the binary's commands (src/cli/mod.rs)");
}

/// The files in `dir`, sorted.
fn files_in(dir: &Path) -> Vec<String> {
    let entries = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name());
    let mut names: Vec<String> = entries.map(|n| n.to_string_lossy().into()).collect();
    names.sort();
    names
}

/// Asserts that a run exited with `code` and, unless 0, said one `error:` line holding `says`.
fn assert_exit(out: &Output, code: i32, says: &str, what: &str) {
    assert_eq!(out.status.code(), Some(code), "{what}: {out:?}");
    let stderr = utf8(&out.stderr);
    let errors = stderr.lines().filter(|l| l.starts_with("error: "));
    let errors: Vec<&str> = errors.collect();
    if code != 0 {
        assert_eq!(errors.len(), 1, "{what}: one `error:` line, got:\n{stderr}");
        let said = errors[0];
        assert!(said.contains(says), "{what}: the binary says `{said}`");
    }
}

/// The exit codes the contract names are 0, 1 and 2, and the binary gives each: the contract's
/// example errors word for word (exit 2, nothing written), a bad `--set` and a usage error (2),
/// an I/O error and no adapter for `--backend gpu` (1), runs that succeed (0).
#[test]
fn the_exit_codes_and_errors_are_the_binarys() {
    let text = contract();
    let section = text.split_once("## Exit codes and errors").map(|(_, s)| s);
    let section = section.and_then(|s| s.split("\n## ").next());
    let section = section.expect("docs/CONTRACT.md has \"## Exit codes and errors\"");
    // Its first item: `- 0: done. 2: bad input (...). 1: anything else (...).`
    let first = section.split("\n- ").nth(1).unwrap_or("");
    let code = |s: &str| s.split_once(':').and_then(|(n, _)| n.trim().parse().ok());
    let codes: BTreeSet<u32> = first.split(". ").filter_map(code).collect();
    let message = format!("{CONTRACT} names exit codes {codes:?}; this test checks 0, 1, 2");
    assert_eq!(codes, BTreeSet::from([0, 1, 2]), "{message}: add a case");
    // The contract's example errors, each reproduced: `error: SOURCE: ...`.
    let quoted = section.split('`').skip(1).step_by(2);
    let examples: Vec<&str> = quoted.filter(|s| s.starts_with("error: ")).collect();
    assert!(examples.len() >= 2, "example errors: {examples:?}");
    for example in examples {
        let dir = tempfile::tempdir().unwrap();
        let rest = example.strip_prefix("error: ").unwrap();
        let out = if let Some(set) = rest.strip_prefix("--set ") {
            let (set, _) = set.split_once(": ").expect("`--set K=V: reason`");
            qjulia(dir.path(), &["render", "--set", set], &[])
        } else {
            // `FILE: TABLE.KEY = VALUE: REASON`
            let (file, assignment) = rest.split_once(": ").expect("`FILE: KEY = VALUE: ...`");
            let (key, value) = assignment.split_once(" = ").expect("KEY = VALUE");
            let value = value.split_once(": ").expect("VALUE: REASON").0;
            let (table, leaf) = key.split_once('.').expect("TABLE.KEY");
            let scene = format!("[{table}]\n{leaf} = {value}\n");
            std::fs::write(dir.path().join(file), scene).unwrap();
            qjulia(dir.path(), &["render", "--scene", file], &[])
        };
        let what = format!("{CONTRACT}'s example error `{example}` (write the binary's there)");
        assert_exit(&out, 2, example, &what);
        let mut written = files_in(dir.path());
        written.retain(|f| !f.ends_with(".toml"));
        assert!(written.is_empty(), "{example}: wrote {written:?}");
    }
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &str, env: &[(&str, &str)]| {
        let args: Vec<&str> = args.split_whitespace().collect();
        qjulia(dir.path(), &args, env)
    };
    let tiny = "--backend cpu --width 8 --height 8";
    // 2: a bad --set names the key; an unknown flag is a usage error.
    let out = run("render --set image.width=0", &[]);
    assert_exit(&out, 2, "image.width", "a bad --set");
    assert_exit(&run("render --no-such-flag", &[]), 2, "", "a usage error");
    // 1: I/O (a folder that is not there), no adapter for `--backend gpu`.
    let out = run(&format!("render -o missing/out.png {tiny}"), &[]);
    assert_exit(&out, 1, "missing/out.png", "an I/O error");
    let no_adapter = [("WGPU_ADAPTER_NAME", "no adapter has this name")];
    let out = run("render --backend gpu --width 8 --height 8", &no_adapter);
    assert_exit(&out, 1, "no GPU adapter", "--backend gpu with no adapter");
    assert!(files_in(dir.path()).is_empty(), "failed runs wrote files");
    // 0: a render on the CPU, and the schema as data.
    let out = run(&format!("render -o ok.png {tiny}"), &[]);
    assert_exit(&out, 0, "", "a render on the CPU");
    assert_eq!(files_in(dir.path()), ["ok.png"]);
    let out = run("schema --json", &[]);
    assert_exit(&out, 0, "", "qjulia schema --json");
    let schema = SchemaJson::new().to_json();
    assert!(utf8(&out.stdout) == schema, "qjulia schema --json");
}
