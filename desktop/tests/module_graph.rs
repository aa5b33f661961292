//! The CLI's files import each other without a cycle: shared pieces (`side_by_side`, the one
//! measurement engine; `csv_out`, `progress`, …) never import a command, and no command imports
//! another through a third. A file or folder of `desktop/src` is a node, named as `crate::…`
//! names it; its edges are the `crate::…` paths in its code (unit tests left out). Mutation:
//! `use crate::commands::compare::CompareArgs` in `side_by_side.rs` (compare imports it) fails it.

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

/// `commands/mask.rs` → `commands::mask`; a folder's files (and its `mod.rs`) → the folder,
/// except `commands/`, whose files are the commands.
fn node(relative: &Path) -> String {
    let parts: Vec<String> = relative
        .with_extension("")
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .filter(|p| p != "mod")
        .collect();
    let depth = if parts.first().is_some_and(|p| p == "commands") {
        2
    } else {
        1
    };
    parts[..parts.len().min(depth)].join("::")
}

fn file_graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for file in files {
        let relative = file.strip_prefix(&src).unwrap();
        let from = node(relative);
        if from == "main" || from == "commands" {
            continue; // they declare every module
        }
        let text = std::fs::read_to_string(&file).unwrap();
        let code = text.split("#[cfg(test)]").next().unwrap();
        let names = graph.entry(from.clone()).or_default();
        for (i, _) in code.match_indices("crate::") {
            let path: String = code[i + "crate::".len()..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            let segments: Vec<&str> = path.split("::").filter(|s| !s.is_empty()).collect();
            let to = match segments.as_slice() {
                ["commands", command, ..] => format!("commands::{command}"),
                [first, ..] => first.to_string(),
                [] => continue,
            };
            if to != from {
                names.insert(to);
            }
        }
    }
    graph
}

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
        if !done.insert(node.to_string()) {
            return None;
        }
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(cycle) = visit(next, graph, path, done) {
                return Some(cycle);
            }
        }
        path.pop();
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|n| visit(n, graph, &mut Vec::new(), &mut done))
}

#[test]
fn no_file_of_the_cli_imports_itself_through_others() {
    let graph = file_graph();
    assert!(
        graph.contains_key("commands::compare") && graph.contains_key("side_by_side"),
        "{graph:#?}"
    );
    assert!(
        graph["cli"].contains("commands::compare"),
        "the parser reads no edge: {graph:#?}"
    );
    if let Some(cycle) = find_cycle(&graph) {
        panic!("file cycle {}\nthe graph: {graph:#?}", cycle.join(" → "));
    }
}
