//! The README is a guide: under 200 lines, and every link in it (and in docs/, data/runs/LOG.md
//! and data/runs/README.md) resolves to a file inside the repository. The pages in docs/ are
//! reference pages, not logs: each is at most 400 lines and cites at most 5 dates.

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
    // The run log and the reference runs' README may cite the web too.
    for file in ["data/runs/LOG.md", "data/runs/README.md"] {
        broken.extend(check_links(&root.join(file), true));
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
    // The checker itself finds a link and a broken one.
    assert_eq!(link_targets("see [a](b.md#c) and [d](e)"), ["b.md#c", "e"]);
}

/// How many dates of the form YYYY-MM-DD (2, 0, two digits, '-', two digits, '-', two digits)
/// `text` holds.
fn count_dates(text: &str) -> usize {
    let b = text.as_bytes();
    let digit = |i: usize| b[i].is_ascii_digit();
    let mut count = 0;
    let mut i = 0;
    while i + 10 <= b.len() {
        let date = b[i] == b'2'
            && b[i + 1] == b'0'
            && digit(i + 2)
            && digit(i + 3)
            && b[i + 4] == b'-'
            && digit(i + 5)
            && digit(i + 6)
            && b[i + 7] == b'-'
            && digit(i + 8)
            && digit(i + 9);
        if date {
            count += 1;
            i += 10;
        } else {
            i += 1;
        }
    }
    count
}

#[test]
fn docs_pages_are_reference_pages_not_logs() {
    // The thresholds are the ones the project's before-stop review uses: a reference page says
    // what is true now (the method, an example, the validation, the current figures), so it
    // stays short and cites few dated measurements; the dated history (runs, sessions,
    // superseded figures) belongs in data/runs/LOG.md, the project's one dated run log.
    const MAX_LINES: usize = 400;
    const MAX_DATES: usize = 5;
    // The date counter itself: two dates, and a run of digits that is no date.
    assert_eq!(count_dates("on 2026-11-28 and 2025-01-02"), 2);
    assert_eq!(count_dates("20261128"), 0);
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut logs = Vec::new();
    for entry in std::fs::read_dir(root.join("docs")).expect("docs") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "md") {
            let text = std::fs::read_to_string(&path).expect("read");
            let lines = text.lines().count();
            // performance.md is one table of current figures, each with the date it was
            // measured (issue 52): there the dates of the table's rows are what the page is
            // for, and only its prose is held to the limit.
            let counted: String = if path.file_name().is_some_and(|n| n == "performance.md") {
                text.lines()
                    .filter(|l| !l.trim_start().starts_with('|'))
                    .collect::<Vec<_>>()
                    .join("\n")
            } else {
                text.clone()
            };
            let dates = count_dates(&counted);
            if lines > MAX_LINES || dates > MAX_DATES {
                logs.push(format!(
                    "{}: {lines} lines (at most {MAX_LINES}), {dates} dates (at most {MAX_DATES})",
                    path.display()
                ));
            }
        }
    }
    assert!(
        logs.is_empty(),
        "pages of docs/ that read as logs (move their dated history to data/runs/LOG.md):\n{}",
        logs.join("\n")
    );
}
