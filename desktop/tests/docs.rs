//! The documentation holds together: every relative link of every Markdown file in the
//! repository reaches a file, and a link to a heading reaches a heading there (GitHub's anchors);
//! the results page and the README's verdict table are what their run files give
//! (`scripts/results.sh`). Mutations: a link to a moved section's old anchor, or a figure of
//! `docs/results.md` edited by hand, fails them.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Every Markdown file under `dir`, build outputs and dependencies left out.
fn markdown(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            if !name.starts_with('.') && name != "target" && name != "node_modules" {
                markdown(&path, out);
            }
        } else if name.ends_with(".md") {
            out.push(path);
        }
    }
}

/// The text with fenced code blocks and inline code blanked, so links in code do not count.
fn prose(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut fenced = false;
    for line in text.split_inclusive('\n') {
        if line.starts_with("```") {
            fenced = !fenced;
            out.push_str(&" ".repeat(line.trim_end_matches('\n').len()));
            out.push_str(&line[line.trim_end_matches('\n').len()..]);
            continue;
        }
        if fenced {
            out.extend(line.chars().map(|c| if c == '\n' { '\n' } else { ' ' }));
            continue;
        }
        let mut in_code = false;
        for c in line.chars() {
            if c == '`' {
                in_code = !in_code;
                out.push(' ');
            } else if in_code && c != '\n' {
                out.push(' ');
            } else {
                out.push(c);
            }
        }
    }
    out
}

/// The targets of the links (`[text](target)`, images too) in `text`.
fn link_targets(text: &str) -> Vec<String> {
    let prose = prose(text);
    let mut targets = Vec::new();
    let mut rest = prose.as_str();
    while let Some(at) = rest.find("](") {
        let after = &rest[at + 2..];
        let end = after.find([')', ' ', '\n']).unwrap_or(after.len());
        if after[end..].starts_with(')') {
            targets.push(after[..end].to_string());
        }
        rest = &after[end..];
    }
    targets
}

/// GitHub's anchor for a heading's text: lower case, letters, digits, `-` and `_` kept,
/// spaces to `-`, the rest dropped.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// Every heading's anchor in a Markdown file (a repeated heading's gets `-1`, `-2`, …);
/// headings in fenced code do not count.
fn anchors(text: &str) -> BTreeSet<String> {
    let mut seen = std::collections::HashMap::new();
    let mut out = BTreeSet::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.starts_with("```") {
            fenced = !fenced;
            continue;
        }
        let hashes = line.chars().take_while(|&c| c == '#').count();
        if fenced || !(1..=6).contains(&hashes) || !line[hashes..].starts_with(' ') {
            continue;
        }
        let s = slug(&line[hashes..].replace(['`', '*'], ""));
        let n = seen.entry(s.clone()).or_insert(0);
        out.insert(if *n == 0 {
            s.clone()
        } else {
            format!("{s}-{n}")
        });
        *n += 1;
    }
    out
}

#[test]
fn every_link_of_the_docs_reaches_its_file_and_heading() {
    let mut files = Vec::new();
    markdown(&root(), &mut files);
    assert!(files.len() > 30, "{files:?}");
    let mut broken = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for target in link_targets(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (path, anchor) = target.split_once('#').unwrap_or((&target, ""));
            let linked = match path {
                "" => file.clone(),
                p => file.parent().unwrap().join(p),
            };
            if !linked.exists() {
                broken.push(format!("{}: no file {target}", file.display()));
            } else if !anchor.is_empty() && linked.extension().is_some_and(|e| e == "md") {
                let there = anchors(&std::fs::read_to_string(&linked).unwrap());
                if !there.contains(anchor) {
                    broken.push(format!("{}: no heading {target}", file.display()));
                }
            }
        }
    }
    assert!(
        broken.is_empty(),
        "{} broken links:\n{}",
        broken.len(),
        broken.join("\n")
    );
}

#[test]
fn the_results_pages_are_what_their_run_files_give() {
    let root = root();
    let out = Command::new(env!("CARGO_BIN_EXE_foveate"))
        .args(["results", "--check", "--root"])
        .arg(&root)
        .output()
        .expect("run foveate results");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The link finder itself: links in code do not count, a link's text may hold brackets and
/// span lines, an image is a link.
#[test]
fn links_are_found_as_markdown_has_them() {
    let text =
        "see [a\nb](x.md#h) and `[no](y.md)`\n```\n[no](z.md)\n```\n![pic](p.png) [[1]](w.md)\n";
    assert_eq!(link_targets(text), ["x.md#h", "p.png", "w.md"]);
    assert_eq!(
        slug("The walk's periphery: its density, or the accumulation?"),
        "the-walks-periphery-its-density-or-the-accumulation"
    );
    let heads = anchors("# A b\n## A b\n```\n# not\n```\n### `Code` heading\n");
    assert_eq!(
        heads.into_iter().collect::<Vec<_>>(),
        ["a-b", "a-b-1", "code-heading"]
    );
}

/// Bytes of every file under `dir`.
fn bytes_under(dir: &Path) -> u64 {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|entry| {
            let path = entry.unwrap().path();
            if path.is_dir() {
                bytes_under(&path)
            } else {
                path.metadata().unwrap().len()
            }
        })
        .sum()
}

/// The front page stays a front page and the docs stay small enough to clone: the README in
/// 120 lines, `docs/` in 4 MiB (pictures as JPEG where they are photographs of a frame, run
/// files trimmed to what a page cites). Mutations: a line added to the README, or a 200 KiB
/// file dropped into a nearly full `docs/`, fails it.
#[test]
fn the_readme_and_the_docs_stay_within_their_limits() {
    const README_LINES: usize = 120;
    const DOCS_BYTES: u64 = 4 << 20;
    let root = root();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(
        lines <= README_LINES,
        "README.md is {lines} lines, over its limit of {README_LINES}: move detail to docs/"
    );
    let docs = bytes_under(&root.join("docs"));
    assert!(
        docs <= DOCS_BYTES,
        "docs/ holds {} KiB, over its limit of {} KiB: shrink pictures and run files",
        docs / 1024,
        DOCS_BYTES / 1024
    );
}

/// The Rust blocks of a Markdown text, each with the file the comment before it names
/// (`<!-- from PATH -->`, or `None`).
fn rust_blocks(text: &str) -> Vec<(Option<String>, Vec<String>)> {
    let mut blocks = Vec::new();
    let mut last_prose = "";
    let mut block: Option<(Option<String>, Vec<String>)> = None;
    for line in text.lines() {
        match (&mut block, line.starts_with("```")) {
            (Some(_), true) => blocks.push(block.take().unwrap()),
            (Some((_, lines)), false) => lines.push(line.to_string()),
            (None, true) if line.starts_with("```rust") => {
                let from = (last_prose.strip_prefix("<!-- from "))
                    .and_then(|rest| rest.strip_suffix(" -->"))
                    .map(str::to_string);
                block = Some((from, Vec::new()));
            }
            (None, true) => {
                // Another language's block: skip to its end.
                block = None;
                last_prose = "```";
            }
            (None, false) if !line.trim().is_empty() => last_prose = line.trim(),
            (None, false) => {}
        }
    }
    blocks
}

/// Every Rust example of `docs/embedding.md` and the README is an excerpt of a file that is
/// compiled (an example, a test): each line of code in it — comments set aside — stands in the
/// file the comment before the block names, so an API change that breaks the file breaks the
/// build, and an excerpt left behind fails here. Mutation: a call renamed in a block (as
/// `record(cmd, &input, …)` was left behind once) fails it.
#[test]
fn every_rust_example_of_the_guide_and_the_readme_is_compiled_code() {
    let root = root();
    let blocks: Vec<_> = ["docs/embedding.md", "README.md"]
        .iter()
        .flat_map(|page| rust_blocks(&std::fs::read_to_string(root.join(page)).unwrap()))
        .collect();
    assert!(blocks.len() >= 4, "{blocks:?}");
    let mut stray = Vec::new();
    for (from, lines) in &blocks {
        let Some(from) = from else {
            stray.push(format!(
                "a block with no <!-- from PATH --> before it: {lines:?}"
            ));
            continue;
        };
        let source = std::fs::read_to_string(root.join(from))
            .unwrap_or_else(|e| panic!("{from}, named before a Rust block: {e}"));
        let source: Vec<&str> = source.lines().map(str::trim).collect();
        for line in lines {
            let code = line.split(" // ").next().unwrap().trim();
            if code.is_empty() || code.starts_with("//") {
                continue;
            }
            if !source.iter().any(|s| s.contains(code)) {
                stray.push(format!("{from}: no line holds `{code}`"));
            }
        }
    }
    assert!(stray.is_empty(), "{}", stray.join("\n"));
}
