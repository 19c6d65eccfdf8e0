//! Imports run one way, down the data flow of docs/architecture.md: a stage never imports a
//! later one, and no two files import each other (directly or round a circle).
//!
//! The stages, earliest first (a module may import its own and earlier ones):
//! error, table, friction, material, output, random < signal, geometry, linalg < input < mesh <
//! fem < scenario, kalker < model < modal < testdata, explicit < contact < rolling < stability <
//! analysis < report < pipeline. The binary (main.rs, cli/) may import anything.
//!
//! What counts as an import: a path `crate::a::b...` or `super::...` in code (comments and
//! doc comments are left out; a brace list is expanded one level).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Stage rank of each top-level module.
fn rank(module: &str) -> Option<u32> {
    Some(match module {
        "error" | "table" | "friction" | "material" | "output" | "random" => 0,
        "signal" | "geometry" | "linalg" => 1,
        "input" => 2,
        "mesh" => 3,
        "fem" => 4,
        "scenario" | "kalker" => 5,
        "model" => 6,
        "modal" => 7,
        "testdata" | "explicit" => 8,
        "contact" => 9,
        "rolling" => 10,
        "stability" => 11,
        "analysis" => 12,
        "report" => 13,
        "pipeline" => 14,
        _ => return None,
    })
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("src") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The code of a file without comments (line comments, doc comments, block comments).
fn code(text: &str) -> String {
    let mut out = String::new();
    let mut chars = text.chars().peekable();
    let mut in_string = false;
    while let Some(c) = chars.next() {
        if in_string {
            out.push(c);
            if c == '\\' {
                if let Some(n) = chars.next() {
                    out.push(n);
                }
            } else if c == '"' {
                in_string = false;
            }
            continue;
        }
        match (c, chars.peek()) {
            ('"', _) => {
                in_string = true;
                out.push(c);
            }
            ('/', Some('/')) => {
                for n in chars.by_ref() {
                    if n == '\n' {
                        out.push('\n');
                        break;
                    }
                }
            }
            ('/', Some('*')) => {
                chars.next();
                let mut last = ' ';
                for n in chars.by_ref() {
                    if last == '*' && n == '/' {
                        break;
                    }
                    last = n;
                }
            }
            _ => out.push(c),
        }
    }
    out
}

/// Module path of a file below src/: `src/a/b.rs` -> [a, b]; `mod.rs` names its folder.
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).expect("under src");
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

/// The import paths of `code` as absolute module paths (`crate::a::b::C` -> [a, b, C]; a brace
/// list `crate::a::{b, c::D}` gives [a, b] and [a, c, D]), `super::` resolved against the
/// file's own module path `me`.
fn imports(code: &str, me: &[String]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for prefix in ["crate::", "super::"] {
        let mut start = 0;
        while let Some(k) = code[start..].find(prefix) {
            let at = start + k;
            start = at + prefix.len();
            // Not part of a longer identifier (`my_crate::`, `xsuper::`).
            let before = code[..at].chars().next_back().unwrap_or(' ');
            if before.is_alphanumeric() || before == '_' || before == ':' {
                continue;
            }
            let mut base: Vec<String> = if prefix == "crate::" {
                Vec::new()
            } else {
                // `super` of `a::b` (file a/b.rs or folder a/b/mod.rs) is `a`.
                me[..me.len().saturating_sub(1)].to_vec()
            };
            let mut rest = &code[at + prefix.len()..];
            while let Some(r) = rest.strip_prefix("super::") {
                base.pop();
                rest = r;
            }
            // The path up to a brace list or the end of the path.
            let head: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            let mut path = base.clone();
            path.extend(head.split("::").filter(|s| !s.is_empty()).map(String::from));
            let after = &rest[head.len()..];
            if head.ends_with("::") && after.starts_with('{') {
                let list: String = after[1..].chars().take_while(|c| *c != '}').collect();
                for item in list.split(',') {
                    let item: String = item
                        .trim()
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                        .collect();
                    let mut p = path.clone();
                    p.extend(
                        item.split("::")
                            .filter(|s| !s.is_empty() && *s != "self")
                            .map(String::from),
                    );
                    out.push(p);
                }
            } else {
                out.push(path);
            }
        }
    }
    out
}

#[test]
fn imports_run_down_the_data_flow_and_files_form_no_circle() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let modules: BTreeMap<Vec<String>, PathBuf> = files
        .iter()
        .map(|f| (module_path(&src, f), f.clone()))
        .collect();
    let mut against = Vec::new();
    let mut edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
    for file in &files {
        let me = module_path(&src, file);
        let top = me.first().cloned().unwrap_or_default();
        if top == "main" || top == "cli" || top == "lib" || me.is_empty() {
            continue;
        }
        let text = code(&std::fs::read_to_string(file).expect("read"));
        for path in imports(&text, &me) {
            let Some(target_top) = path.first() else {
                continue;
            };
            if let (Some(a), Some(b)) = (rank(&top), rank(target_top)) {
                if b > a {
                    against.push(format!(
                        "{}: imports {} (stage {b} > {a})",
                        file.display(),
                        path.join("::")
                    ));
                }
            }
            // The longest prefix of the path that is a file.
            let target = (1..=path.len())
                .rev()
                .map(|n| path[..n].to_vec())
                .find(|p| modules.contains_key(p));
            if let Some(t) = target {
                // A module's own children and its parent's re-exports are not circles of files
                // unless both files name each other.
                if t != me {
                    edges.entry(me.clone()).or_default().insert(t);
                }
            }
        }
    }
    assert!(
        against.is_empty(),
        "imports against the data flow:\n{}",
        against.join("\n")
    );
    // Circles: a depth-first search for a back edge among files (mod.rs files that only
    // declare and re-export their children are skipped as targets of their children).
    let is_decl_only = |m: &Vec<String>| {
        modules.get(m).is_some_and(|f| {
            f.file_name()
                .is_some_and(|n| n == "mod.rs" || n == "lib.rs")
        })
    };
    let mut circles = Vec::new();
    for (from, targets) in &edges {
        for to in targets {
            if is_decl_only(to) && from.starts_with(to) {
                continue;
            }
            // Does `to` reach `from`?
            let mut stack = vec![to.clone()];
            let mut seen = BTreeSet::new();
            while let Some(m) = stack.pop() {
                if &m == from {
                    circles.push(format!("{} <-> {}", from.join("::"), to.join("::")));
                    break;
                }
                if !seen.insert(m.clone()) {
                    continue;
                }
                for n in edges.get(&m).into_iter().flatten() {
                    if is_decl_only(n) && m.starts_with(n) {
                        continue;
                    }
                    stack.push(n.clone());
                }
            }
        }
    }
    circles.sort();
    circles.dedup();
    assert!(
        circles.is_empty(),
        "files importing each other:\n{}",
        circles.join("\n")
    );

    // Folders: an import from `a::x::...` to `a::y::...` (x != y) is an edge between the
    // siblings `a::x` and `a::y`, at every depth (top-level modules included); the siblings
    // must form no circle either.
    let mut sibling_edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
    for (from, targets) in &edges {
        for to in targets {
            let common = from.iter().zip(to).take_while(|(a, b)| a == b).count();
            if from.len() > common && to.len() > common {
                sibling_edges
                    .entry(from[..=common].to_vec())
                    .or_default()
                    .insert(to[..=common].to_vec());
            }
        }
    }
    let mut folder_circles = Vec::new();
    for (from, targets) in &sibling_edges {
        for to in targets {
            let mut stack = vec![to.clone()];
            let mut seen = BTreeSet::new();
            while let Some(m) = stack.pop() {
                if &m == from {
                    folder_circles.push(format!("{} <-> {}", from.join("::"), to.join("::")));
                    break;
                }
                if seen.insert(m.clone()) {
                    stack.extend(sibling_edges.get(&m).into_iter().flatten().cloned());
                }
            }
        }
    }
    folder_circles.sort();
    assert!(
        folder_circles.is_empty(),
        "modules or folders importing each other:\n{}",
        folder_circles.join("\n")
    );
}
