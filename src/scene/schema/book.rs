//! The book's scene-file block (docs/book/scene-file.md), written from the schema's tables, and
//! the test that holds the book to it.

use super::{SCHEMA, TABLES};
use crate::scene::Scene;

/// The scene-file block of the book's docs/book/scene-file.md (between its ```` ```toml ````
/// fences): every table and key with its default and comment, comments aligned in one column.
pub fn readme_block() -> String {
    let defaults = Scene::default();
    let mut out = String::new();
    for (i, table) in TABLES.iter().enumerate() {
        if i > 0 {
            out.push('\n');
        }
        readme_line(&mut out, &format!("[{}]", table.name), table.readme);
        for key in SCHEMA.iter().filter(|k| k.table() == table.name) {
            let text = format!("{} = {}", key.leaf(), key.kind.value(&defaults));
            let range = key.kind.range_text().unwrap_or_default();
            readme_line(&mut out, &text, &key.readme.replace("{range}", &range));
        }
    }
    out
}

/// Comments start in this column (from 0) where the text leaves room.
const README_COMMENT_COLUMN: usize = 34;

fn readme_line(out: &mut String, text: &str, comment: &str) {
    if comment.is_empty() {
        out.push_str(text);
    } else {
        let width = README_COMMENT_COLUMN - 1;
        out.push_str(&format!("{text:<width$} # {comment}"));
    }
    out.push('\n');
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The book's scene-file chapter, whose first ```` ```toml ```` block is the scene file.
    const BOOK_SCENE_FILE: &str = "docs/book/scene-file.md";

    /// The block between the first ```` ```toml ```` fences under the chapter's "# The scene
    /// file".
    fn book_scene_block() -> String {
        let path = format!("{}/{BOOK_SCENE_FILE}", env!("CARGO_MANIFEST_DIR"));
        let chapter = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("{BOOK_SCENE_FILE} is readable: {e}"));
        let section = chapter
            .split_once("# The scene file\n")
            .unwrap_or_else(|| panic!("{BOOK_SCENE_FILE} has a \"# The scene file\" heading"))
            .1;
        let block = section
            .split_once("```toml\n")
            .unwrap_or_else(|| panic!("{BOOK_SCENE_FILE} has a ```toml block"))
            .1;
        block
            .split_once("```")
            .expect("the ```toml block is closed")
            .0
            .to_string()
    }

    #[test]
    fn book_scene_block_is_the_schemas() {
        let book = book_scene_block();
        let schema = readme_block();
        if book == schema {
            return;
        }
        let old: Vec<&str> = book.lines().collect();
        let new: Vec<&str> = schema.lines().collect();
        panic!(
            "{BOOK_SCENE_FILE}'s scene-file block (-) differs from the schema in src/scene/mod.rs \
             (+):\n\
             {}\nthe block should read:\n```toml\n{schema}```",
            line_diff(&old, &new)
        );
    }

    /// The lines only `old` has (-) and only `new` has (+), by a longest common subsequence,
    /// each with its line number in the block.
    fn line_diff(old: &[&str], new: &[&str]) -> String {
        // common[i][j]: the longest common subsequence of old[i..] and new[j..].
        let mut common = vec![vec![0usize; new.len() + 1]; old.len() + 1];
        for i in (0..old.len()).rev() {
            for j in (0..new.len()).rev() {
                common[i][j] = if old[i] == new[j] {
                    common[i + 1][j + 1] + 1
                } else {
                    common[i + 1][j].max(common[i][j + 1])
                };
            }
        }
        let (mut i, mut j, mut out) = (0, 0, String::new());
        while i < old.len() || j < new.len() {
            if i < old.len() && j < new.len() && old[i] == new[j] {
                (i, j) = (i + 1, j + 1);
            } else if j == new.len() || (i < old.len() && common[i + 1][j] >= common[i][j + 1]) {
                out.push_str(&format!("line {:>3} - {}\n", i + 1, old[i]));
                i += 1;
            } else {
                out.push_str(&format!("line {:>3} + {}\n", j + 1, new[j]));
                j += 1;
            }
        }
        out
    }

    #[test]
    fn the_readme_diff_names_only_the_lines_that_differ() {
        assert_eq!(line_diff(&["a", "c"], &["a", "b", "c"]), "line   2 + b\n");
        assert_eq!(
            line_diff(&["a", "b", "c"], &["a", "x", "c"]),
            "line   2 - b\nline   2 + x\n"
        );
        assert_eq!(line_diff(&["a", "b"], &["a"]), "line   2 - b\n");
    }
}
