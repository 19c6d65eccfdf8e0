//! The README is a guide: under 200 lines, and every link in it (and in docs/) resolves to a
//! file inside the repository.

use std::path::Path;

/// The targets of the markdown links `[text](target)` in `text`.
fn link_targets(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(k) = rest.find("](") {
        rest = &rest[k + 2..];
        if let Some(end) = rest.find(')') {
            out.push(rest[..end].trim().to_string());
        }
    }
    out
}

fn check_links(file: &Path, allow_external: bool) -> Vec<String> {
    let text = std::fs::read_to_string(file).expect("read");
    let dir = file.parent().expect("folder");
    let mut broken = Vec::new();
    for target in link_targets(&text) {
        if target.starts_with("http://") || target.starts_with("https://") {
            if !allow_external {
                broken.push(format!("{}: external link {target}", file.display()));
            }
            continue;
        }
        let path = target.split('#').next().unwrap_or("");
        if path.is_empty() {
            continue; // an anchor in the same file
        }
        if !dir.join(path).exists() {
            broken.push(format!("{}: {target} does not exist", file.display()));
        }
    }
    broken
}

#[test]
fn readme_is_short_and_its_links_stay_inside_the_repository() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = root.join("README.md");
    let lines = std::fs::read_to_string(&readme)
        .expect("README")
        .lines()
        .count();
    assert!(lines < 200, "README.md has {lines} lines");
    let mut broken = check_links(&readme, false);
    // docs/ may cite published sources on the web; its links inside the repository must exist.
    for entry in std::fs::read_dir(root.join("docs")).expect("docs") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "md") {
            broken.extend(check_links(&path, true));
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
    // The checker itself finds a link and a broken one.
    assert_eq!(link_targets("see [a](b.md#c) and [d](e)"), ["b.md#c", "e"]);
}
