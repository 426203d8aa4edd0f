//! The README and the book (docs/, built by `mdbook build docs/book`): every relative link and
//! image resolves to a file, every `#anchor` to a heading of its page, a book page links only
//! within docs/ (the book's source, so that the built book keeps the link), and docs/SUMMARY.md
//! lists every page under docs/ and nothing else. No mdbook needed: plain string scanning.

use super::files_under;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Component, Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The book's source folder (book.toml's `src = ".."`): docs/.
fn book_src() -> PathBuf {
    root().join("docs")
}

/// The pages checked: README.md and every page of the book.
fn pages() -> Vec<PathBuf> {
    let mut pages = vec![root().join("README.md")];
    pages.extend(files_under(&book_src(), &["md"]));
    pages
}

/// `path` relative to the repository, for messages.
fn shown(path: &Path) -> String {
    path.strip_prefix(root())
        .unwrap_or(path)
        .display()
        .to_string()
}

/// `text` with code blanked out (fenced and indented blocks, inline code spans), each of its
/// characters but newlines made a space, so that offsets and line numbers stay.
fn blank_code(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    // The open fence's character and length.
    let mut fence: Option<(char, usize)> = None;
    let mut previous_blank = true;
    let mut previous_indented_code = false;
    for line in text.split_inclusive('\n') {
        let trimmed = line.trim_start();
        let marker = trimmed.chars().next().filter(|c| *c == '`' || *c == '~');
        let run = marker.map_or(0, |m| trimmed.chars().take_while(|c| *c == m).count());
        let code = if let Some((m, n)) = fence {
            if marker == Some(m) && run >= n && trimmed[run..].trim().is_empty() {
                fence = None;
            }
            true
        } else if run >= 3 {
            fence = Some((marker.expect("a fence marker"), run));
            true
        } else {
            let indented = line.starts_with("    ") || line.starts_with('\t');
            indented && !trimmed.is_empty() && (previous_blank || previous_indented_code)
        };
        previous_indented_code = code && fence.is_none() && run < 3;
        previous_blank = trimmed.is_empty();
        if code {
            out.extend(line.chars().map(|c| if c == '\n' { '\n' } else { ' ' }));
        } else {
            out.push_str(line);
        }
    }
    blank_code_spans(&out)
}

/// `text` with its inline code spans (a run of backticks to the next run of the same length)
/// blanked out; a run without its match is literal.
fn blank_code_spans(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = chars.clone();
    let run_at = |i: usize| chars[i..].iter().take_while(|c| **c == '`').count();
    let mut i = 0;
    while i < chars.len() {
        if chars[i] != '`' {
            i += 1;
            continue;
        }
        let n = run_at(i);
        let mut j = i + n;
        let close = loop {
            if j >= chars.len() {
                break None;
            }
            if chars[j] == '`' {
                let m = run_at(j);
                if m == n {
                    break Some(j);
                }
                j += m;
            } else {
                j += 1;
            }
        };
        match close {
            Some(j) => {
                for c in &mut out[i..j + n] {
                    if *c != '\n' {
                        *c = ' ';
                    }
                }
                i = j + n;
            }
            None => i += n,
        }
    }
    out.into_iter().collect()
}

/// A link or image target found in a page: its line (from 1) and the target as written.
#[derive(Debug, PartialEq)]
struct Link {
    line: usize,
    target: String,
}

/// Every inline link and image (`[text](target)`, `![alt](target "title")`), reference
/// definition (`[name]: target`) and HTML `src`/`href` outside code, in order.
fn links(text: &str) -> Vec<Link> {
    let text = blank_code(text);
    let line_of = |offset: usize| text[..offset].matches('\n').count() + 1;
    let mut out = Vec::new();
    for (at, _) in text.match_indices("](") {
        let start = at + 2;
        let rest = &text[start..];
        let rest_trimmed = rest.trim_start();
        let target = if let Some(inner) = rest_trimmed.strip_prefix('<') {
            inner.split('>').next().unwrap_or("").to_string()
        } else {
            let mut depth = 0usize;
            let mut end = rest_trimmed.len();
            for (k, c) in rest_trimmed.char_indices() {
                match c {
                    '(' => depth += 1,
                    ')' if depth == 0 => {
                        end = k;
                        break;
                    }
                    ')' => depth -= 1,
                    c if c.is_whitespace() => {
                        end = k;
                        break;
                    }
                    _ => {}
                }
            }
            rest_trimmed[..end].to_string()
        };
        out.push((start, target));
    }
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let trimmed = line.trim_start();
        if line.len() - trimmed.len() <= 3
            && trimmed.starts_with('[')
            && !trimmed.starts_with("[^")
            && let Some((_, rest)) = trimmed.split_once("]:")
            && let Some(target) = rest.split_whitespace().next()
        {
            let target = target.trim_start_matches('<').trim_end_matches('>');
            out.push((offset, target.to_string()));
        }
        offset += line.len();
    }
    for attribute in ["src=\"", "href=\""] {
        for (at, _) in text.match_indices(attribute) {
            let start = at + attribute.len();
            let target = text[start..].split('"').next().unwrap_or("").to_string();
            out.push((start, target));
        }
    }
    out.sort_by_key(|(offset, _)| *offset);
    out.into_iter()
        .map(|(offset, target)| Link {
            line: line_of(offset),
            target,
        })
        .collect()
}

/// A heading's anchor as GitHub and mdBook make it: lowercase, whitespace to '-', letters,
/// digits, '-' and '_' kept, everything else dropped.
fn slug(heading: &str) -> String {
    heading
        .chars()
        .filter_map(|c| {
            if c.is_alphanumeric() || c == '-' || c == '_' {
                Some(c.to_ascii_lowercase())
            } else if c.is_whitespace() {
                Some('-')
            } else {
                None
            }
        })
        .collect()
}

/// The anchors of a page's ATX headings (outside fenced code), repeats numbered `-1`, `-2`, ...
/// as GitHub and mdBook number them.
fn anchors(text: &str) -> BTreeSet<String> {
    let blanked = blank_code(text);
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    let mut out = BTreeSet::new();
    for (line, kept) in text.lines().zip(blanked.lines()) {
        // A heading is found in the blanked text (so not inside a code block) but its words are
        // taken from the page, code spans included.
        let kept = kept.trim_start();
        let hashes = kept.chars().take_while(|c| *c == '#').count();
        if !(1..=6).contains(&hashes) || !kept[hashes..].starts_with(' ') {
            continue;
        }
        let words = line.trim_start()[hashes..]
            .trim()
            .trim_end_matches('#')
            .trim();
        let base = slug(words);
        let count = seen.entry(base.clone()).or_insert(0);
        out.insert(if *count == 0 {
            base.clone()
        } else {
            format!("{base}-{count}")
        });
        *count += 1;
    }
    out
}

/// `path` with `.` and `..` resolved lexically.
fn normalise(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// Whether a target leaves the repository's files (a URL, mail, ...): not checked.
fn is_external(target: &str) -> bool {
    target.contains("://") || target.starts_with("mailto:") || target.starts_with("//")
}

/// What is wrong with the links of one page, one line each.
fn link_problems(page: &Path, text: &str) -> Vec<String> {
    let in_book = page.starts_with(book_src());
    let dir = page.parent().expect("a page is in a folder");
    let mut problems = Vec::new();
    for Link { line, target } in links(text) {
        if is_external(&target) {
            continue;
        }
        let at = format!("{}:{line}: ({target})", shown(page));
        let (path, fragment) = match target.split_once('#') {
            Some((path, fragment)) => (path, Some(fragment)),
            None => (target.as_str(), None),
        };
        let path = path.replace("%20", " ");
        let file = if path.is_empty() {
            page.to_path_buf()
        } else if path.starts_with('/') {
            problems.push(format!(
                "{at}: an absolute path; make it relative to the page"
            ));
            continue;
        } else {
            normalise(&dir.join(&path))
        };
        if !file.exists() {
            problems.push(format!("{at}: no such file {}", shown(&file)));
            continue;
        }
        if in_book && !file.starts_with(book_src()) {
            problems.push(format!(
                "{at}: leaves docs/, the book's source, so the built book loses it"
            ));
        }
        if in_book && file.is_dir() {
            problems.push(format!("{at}: a folder; the built book has no page for it"));
        }
        if let Some(fragment) = fragment.filter(|f| !f.is_empty())
            && file.extension().is_some_and(|e| e == "md")
            && !anchors(&std::fs::read_to_string(&file).expect("a page is readable"))
                .contains(fragment)
        {
            problems.push(format!(
                "{at}: {} has no heading with the anchor #{fragment}",
                shown(&file)
            ));
        }
    }
    problems
}

#[test]
fn every_relative_link_and_anchor_resolves() {
    let mut problems = Vec::new();
    for page in pages() {
        let text = std::fs::read_to_string(&page).expect("a page is readable");
        problems.extend(link_problems(&page, &text));
    }
    assert!(
        problems.is_empty(),
        "{} broken link(s):\n{}",
        problems.len(),
        problems.join("\n")
    );
}

#[test]
fn the_summary_lists_every_page_of_the_book_once() {
    let summary_path = book_src().join("SUMMARY.md");
    let summary = std::fs::read_to_string(&summary_path).expect("docs/SUMMARY.md is readable");
    let mut listed = BTreeMap::new();
    let mut problems = Vec::new();
    for Link { line, target } in links(&summary) {
        let file = normalise(&book_src().join(target.split('#').next().unwrap_or("")));
        if !file.is_file() {
            problems.push(format!(
                "docs/SUMMARY.md:{line}: no such page {}",
                shown(&file)
            ));
        }
        if let Some(first) = listed.insert(file.clone(), line) {
            problems.push(format!(
                "docs/SUMMARY.md:{line}: {} is listed already on line {first}",
                shown(&file)
            ));
        }
    }
    for page in files_under(&book_src(), &["md"]) {
        if page != summary_path && !listed.contains_key(&page) {
            problems.push(format!(
                "{} is not in docs/SUMMARY.md, so the book does not show it",
                shown(&page)
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_scanner_finds_links_and_skips_code() {
    let text = r#"# A `code` heading
see [a](a.md#x) and ![b](img/b.png "title") and `[not](code.md)`, a span `over
[not](two-lines.md)` lines

```toml
[not](fenced.md)
```

    [not](indented.md)

[c]: c.md
<img src="d.png"> [e](<e f.md>) [g](g(1).md)
"#;
    let found: Vec<(usize, String)> = links(text)
        .into_iter()
        .map(|l| (l.line, l.target))
        .collect();
    let expected: Vec<(usize, String)> = [
        (2, "a.md#x"),
        (2, "img/b.png"),
        (11, "c.md"),
        (12, "d.png"),
        (12, "e f.md"),
        (12, "g(1).md"),
    ]
    .iter()
    .map(|(line, target)| (*line, target.to_string()))
    .collect();
    assert_eq!(found, expected);

    let headings = r#"# The cut (exact)
## f64 on the GPU
# Views: `render2d`
# Views: `render2d`
```
# not a heading
```
"#;
    let expected: BTreeSet<String> = [
        "the-cut-exact",
        "f64-on-the-gpu",
        "views-render2d",
        "views-render2d-1",
    ]
    .into_iter()
    .map(String::from)
    .collect();
    assert_eq!(anchors(headings), expected);
}
