//! No source file grows past 600 lines unasked: every `.rs` and `.wgsl` file under src/,
//! shaders/ and tests/ (recursively) is under 600 lines, or says why it is longer in a line of
//! its first 30 that holds "Why it passes 600 lines:" (in its opening `//!` doc or header
//! comment). A long file is split into modules; a reason is for a file that cannot be (a twin of
//! a shader, mirrored function by function).

use super::files_under;
use std::fs;
use std::path::PathBuf;

/// The most lines a file may have without a reason.
const LIMIT: usize = 600;
/// How far from its top a file's reason may be.
const HEADER_LINES: usize = 30;
/// What the reason's line holds.
const REASON: &str = "Why it passes 600 lines:";

/// Whether `text` is too long: LIMIT lines or more, and no reason in its first lines.
fn too_long(text: &str) -> Option<usize> {
    let lines = text.lines().count();
    let reason = text.lines().take(HEADER_LINES).any(|l| l.contains(REASON));
    (lines >= LIMIT && !reason).then_some(lines)
}

#[test]
fn no_source_file_passes_600_lines_without_a_reason() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["src", "shaders", "tests"] {
        files.extend(files_under(&root.join(dir), &["rs", "wgsl"]));
    }
    assert!(files.len() > 50, "the walk found too little: {files:?}");
    let long: Vec<String> = files
        .iter()
        .filter_map(|path| {
            let text = fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
            let lines = too_long(&text)?;
            let name = path.strip_prefix(&root).unwrap_or(path).display();
            Some(format!("{name}: {lines} lines"))
        })
        .collect();
    assert!(
        long.is_empty(),
        "files of {LIMIT} lines or more with no line holding \"{REASON}\" in their first \
         {HEADER_LINES}: split them into modules, or say why at the top:\n{}",
        long.join("\n")
    );
}

/// The check itself, on texts that are known.
#[test]
fn the_check_counts_lines_and_finds_the_reason() {
    let body = "x\n".repeat(LIMIT - 2);
    assert_eq!(too_long(&format!("//! short\n{body}")), None);
    assert_eq!(too_long(&format!("//! long\n{body}x\n")), Some(LIMIT));
    let why = format!("//! A twin.\n//!\n//! {REASON} it mirrors its shader.\n{body}");
    assert_eq!(too_long(&why), None);
    let late = format!(
        "//! A twin.\n{}// {REASON} too late\n{body}",
        "\n".repeat(40)
    );
    assert_eq!(too_long(&late), Some(LIMIT + 40));
}
