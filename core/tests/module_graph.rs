//! The module structure DESIGN.md asks for, read from the sources: which top-level module of
//! `core/src` names which other (`crate::name`, in code, docs and tests alike). The vocabulary
//! imports nothing of ours, and the graph has no cycle — in particular no two modules import
//! each other. Mutation: `use crate::plan::ConfigError` back in `foveation/` (plan imports
//! foveation) or a doc link from `plan` to `render` fails it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Top-level module → the other top-level modules its files name as `crate::module`.
fn module_graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for file in files {
        let relative = file.strip_prefix(&src).unwrap();
        let first = relative
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let module = first.trim_end_matches(".rs").to_string();
        if module == "lib" {
            continue; // the crate root declares every module
        }
        let text = std::fs::read_to_string(&file).unwrap();
        assert!(
            !text.contains("crate::{"),
            "{}: name modules one path at a time (`crate::a::…`), so this check sees them",
            relative.display()
        );
        let names = graph.entry(module.clone()).or_default();
        for (i, _) in text.match_indices("crate::") {
            let rest = &text[i + "crate::".len()..];
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            // Items of the crate root (`crate::plan` the function) count as `plan`.
            if !name.is_empty() && name != module {
                names.insert(name);
            }
        }
    }
    graph
}

#[test]
fn the_vocabulary_is_a_leaf() {
    let graph = module_graph();
    assert_eq!(
        graph.get("vocab"),
        Some(&BTreeSet::new()),
        "vocab imports {:?}",
        graph.get("vocab")
    );
}

/// The GPU layer reads frames back into the vocabulary's image; it knows nothing of how images
/// are compared. Mutation: `use crate::metrics::RgbaImage` back in `gpu/swapchain.rs`.
#[test]
fn the_gpu_layer_imports_no_metrics() {
    let graph = module_graph();
    let gpu = &graph["gpu"];
    assert!(!gpu.contains("metrics"), "gpu imports {gpu:?}");
}

/// The first cycle in `graph`, if any.
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(start) = path.iter().position(|n| n == node) {
            let mut cycle = path[start..].to_vec();
            cycle.push(node.to_string());
            return Some(cycle);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(cycle) = visit(next, graph, path, done) {
                return Some(cycle);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|node| visit(node, graph, &mut Vec::new(), &mut done))
}

#[test]
fn no_module_imports_itself_through_others() {
    let graph = module_graph();
    if let Some(cycle) = find_cycle(&graph) {
        panic!("module cycle: {}\nthe graph: {graph:#?}", cycle.join(" → "));
    }
}

/// The names a folder's `mod.rs` re-exports (`pub use file::{A, B}`), by the file they come
/// from: a sibling naming `super::A` imports that file.
fn reexports(mod_rs: &str, files: &BTreeSet<String>) -> BTreeMap<String, String> {
    let mut items = BTreeMap::new();
    for (i, _) in mod_rs.match_indices("pub use ") {
        let rest = &mod_rs[i + "pub use ".len()..];
        let statement = &rest[..rest.find(';').unwrap()];
        let Some((file, names)) = statement.split_once("::") else {
            continue;
        };
        if !files.contains(file) {
            continue;
        }
        for name in names.split(|c: char| "{}, \n".contains(c)) {
            if !name.is_empty() {
                items.insert(name.to_string(), file.to_string());
            }
        }
    }
    items
}

/// File → the sibling files it names, inside one folder of `core/src` (`super::file`, a name
/// `mod.rs` re-exports from a file, or `crate::folder::…` alike). `mod.rs` and tests left out.
fn file_graph(folder: &str) -> BTreeMap<String, BTreeSet<String>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("src")
        .join(folder);
    let stem = |p: &Path| p.file_stem().unwrap().to_string_lossy().to_string();
    let files: BTreeSet<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .map(|p| stem(&p))
        .filter(|f| f != "mod" && !f.ends_with("tests"))
        .collect();
    let items = reexports(
        &std::fs::read_to_string(dir.join("mod.rs")).unwrap(),
        &files,
    );
    let mut graph = BTreeMap::new();
    for file in &files {
        let text = std::fs::read_to_string(dir.join(format!("{file}.rs"))).unwrap();
        // Unit tests inside the file may use anything.
        let code = text.split("#[cfg(test)]").next().unwrap();
        let mut names = BTreeSet::new();
        let prefix = format!("crate::{folder}::");
        for start in ["super::", prefix.as_str()] {
            for (i, _) in code.match_indices(start) {
                let rest = &code[i + start.len()..];
                // `super::{a::B, C}` or `super::a::B` or `super::C`.
                let paths = if let Some(group) = rest.strip_prefix('{') {
                    group[..group.find('}').unwrap_or(group.len())].to_string()
                } else {
                    rest.chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect()
                };
                for path in paths.split(',') {
                    let first: String = path
                        .trim()
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    let target = if files.contains(&first) {
                        Some(first)
                    } else {
                        items.get(&first).cloned()
                    };
                    if let Some(target) = target.filter(|t| t != file) {
                        names.insert(target);
                    }
                }
            }
        }
        graph.insert(file.clone(), names);
    }
    graph
}

/// DESIGN.md: the foveation layer imports nothing of foveate's scene renderer, neither
/// directly nor through `render`, the public front that re-exports both; the renderer hands
/// the layer its scene as an engine would. Mutation: `use crate::scene_renderer::…` or
/// `use crate::render::Renderer` in a file of `foveation_layer/` fails it.
#[test]
fn the_foveation_layer_imports_nothing_of_the_scene_renderer() {
    let graph = module_graph();
    let layer = &graph["foveation_layer"];
    assert!(graph.contains_key("scene_renderer"), "{graph:?}");
    for above in ["scene_renderer", "render"] {
        assert!(!layer.contains(above), "foveation_layer imports {layer:?}");
    }
    assert!(
        graph["scene_renderer"].contains("foveation_layer"),
        "the renderer draws through the layer: {graph:?}"
    );
}

/// DESIGN.md: the recorder interface (what a frame's commands go through, to Vulkan or to
/// the command log) is a leaf of the layer's folder. Mutation: `use super::stats::DrawTally`
/// in `recorder.rs` fails it.
#[test]
fn the_recorder_interface_is_a_leaf() {
    let graph = file_graph("foveation_layer");
    assert_eq!(graph["recorder"], BTreeSet::new());
}

/// DESIGN.md: inside the layer's, the renderer's and `plan/`'s folders no two files import
/// each other, through others either. Mutation: `use super::layer_engine::…` in `record.rs`
/// (`layer_engine` names `record` through `layer`), or a `plan/model.rs` item `derive.rs`
/// names while `model.rs` names `derive.rs`, fails it.
#[test]
fn no_file_of_the_layer_the_renderer_or_plan_imports_itself_through_others() {
    for folder in ["plan", "foveation_layer", "scene_renderer"] {
        let graph = file_graph(folder);
        assert!(graph.len() > 5, "{folder}: {graph:?}");
        if let Some(cycle) = find_cycle(&graph) {
            panic!(
                "{folder}/: file cycle {}\nthe graph: {graph:#?}",
                cycle.join(" → ")
            );
        }
    }
}

// ---- Size limits: no file of `core/src` or `desktop/src` over 600 lines, no function in the
// workspace's code over 120 (DESIGN.md: a technique reads top to bottom). Mutation: ten lines
// more in `stereo_scene::scene_targets` (116 lines) or a 601-line file (in either) fails them.

const MAX_FILE_LINES: usize = 600;
const MAX_FUNCTION_LINES: usize = 120;

fn sources(folder: &str) -> Vec<PathBuf> {
    let mut files = Vec::new();
    rust_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join(folder),
        &mut files,
    );
    files.sort();
    files
}

/// A line as code: comments, string and character literals blanked out, so their braces do
/// not count.
fn code_of(line: &str) -> String {
    let mut out = String::new();
    let mut chars = line.chars().peekable();
    let mut in_string = false;
    while let Some(c) = chars.next() {
        match (in_string, c) {
            (true, '\\') => {
                chars.next();
            }
            (true, '"') => in_string = false,
            (true, _) => {}
            (false, '"') => in_string = true,
            (false, '/') if chars.peek() == Some(&'/') => break,
            (false, '\'') => {
                // A character literal ('{', '\n') is skipped whole; a lifetime ('a) is not one.
                let rest: String = chars.clone().take(3).collect();
                if rest.starts_with('\\') {
                    let end = rest.find('\'').map_or(0, |e| e + 1);
                    chars.nth(end.max(2) - 1);
                } else if rest.chars().nth(1) == Some('\'') {
                    chars.nth(1);
                }
            }
            (false, c) => out.push(c),
        }
    }
    out
}

/// Each function's name, first line and length in lines (its signature to its closing brace).
fn functions(text: &str) -> Vec<(String, usize, usize)> {
    let lines: Vec<String> = text.lines().map(code_of).collect();
    let mut found = Vec::new();
    for (start, line) in lines.iter().enumerate() {
        let Some(at) = line.find("fn ").filter(|&i| {
            i == 0
                || !line.as_bytes()[i - 1].is_ascii_alphanumeric() && line.as_bytes()[i - 1] != b'_'
        }) else {
            continue;
        };
        let name: String = line[at + 3..]
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if name.is_empty() {
            continue; // `fn(` types
        }
        let mut depth = 0i32;
        let mut opened = false;
        // Brackets of the signature: a `;` inside them (`[f32; 2]`) ends nothing.
        let mut brackets = 0i32;
        'lines: for (end, l) in lines.iter().enumerate().skip(start) {
            for c in l.chars() {
                match c {
                    '{' => {
                        depth += 1;
                        opened = true;
                    }
                    '}' => depth -= 1,
                    '(' | '[' if !opened => brackets += 1,
                    ')' | ']' if !opened => brackets -= 1,
                    ';' if !opened && brackets == 0 => break 'lines, // a declaration without a body
                    _ => {}
                }
                if opened && depth == 0 {
                    found.push((name.clone(), start + 1, end - start + 1));
                    break 'lines;
                }
            }
        }
    }
    found
}

/// `core/src` and the command line's `desktop/src` (DEVELOPERS: no file over 600 lines in
/// `core/` or `desktop/`; a command too long for one file is a folder: its options, its rows,
/// its printing).
#[test]
fn no_file_in_core_or_the_cli_is_over_600_lines() {
    let files: Vec<PathBuf> = ["src", "../desktop/src"]
        .into_iter()
        .flat_map(sources)
        .collect();
    assert!(files.len() > 150, "{files:?}");
    assert!(
        files.iter().any(|f| f.ends_with("commands/flicker/mod.rs")),
        "the command line's files are read"
    );
    let long: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let n = std::fs::read_to_string(f).unwrap().lines().count();
            (n > MAX_FILE_LINES).then(|| format!("{} ({n} lines)", f.display()))
        })
        .collect();
    assert!(long.is_empty(), "over {MAX_FILE_LINES} lines: {long:#?}");
}

/// Every function of the workspace: the library, the command line, the Android demo, the
/// tests' support and the examples (DEVELOPERS: no function over 120 lines).
#[test]
fn no_function_in_the_workspace_is_over_120_lines() {
    let mut long = Vec::new();
    let mut seen = 0;
    let folders = [
        "src",
        "examples",
        "tests",
        "../desktop/src",
        "../android/src",
        "../tests/support",
    ];
    for folder in folders {
        for file in sources(folder) {
            let text = std::fs::read_to_string(&file).unwrap();
            for (name, line, length) in functions(&text) {
                seen += 1;
                if length > MAX_FUNCTION_LINES {
                    long.push(format!("{}:{line} {name} ({length} lines)", file.display()));
                }
            }
        }
    }
    assert!(seen > 200, "functions found: {seen}");
    assert!(
        long.is_empty(),
        "over {MAX_FUNCTION_LINES} lines: {long:#?}"
    );
}

/// The counter itself: a function's braces in strings, characters and comments do not count,
/// and its length runs from `fn` to the closing brace.
#[test]
fn function_lengths_are_counted_from_fn_to_its_closing_brace() {
    let text = "fn a() {\n    let s = \"}\";\n    let c = '{';\n    // }\n}\nfn b(x: &'static str);\nfn c<'a>(x: &'a u8) -> u8 {\n    *x\n}\nfn d(\n    x: [f32; 2],\n) {\n}\n";
    let found = functions(text);
    assert_eq!(
        found,
        vec![
            ("a".to_string(), 1, 5),
            ("c".to_string(), 7, 3),
            // A `;` in the signature's brackets (an array type) is not a declaration's end:
            // the counter once skipped such functions (`culling::cull`, 241 lines).
            ("d".to_string(), 10, 4)
        ],
        "{found:?}"
    );
}
