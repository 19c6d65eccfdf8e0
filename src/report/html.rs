//! The report's HTML page from its own markdown: headings (with a table of contents of the
//! `##` sections), paragraphs (consecutive lines form one, as in markdown, so charts written
//! on consecutive lines stand side by side), tables (`\|` is a literal bar in a cell), lists,
//! images, links, `**bold**` and `` `code` `` (everywhere: cells, list items, headings).
//! Everything else is text, escaped. A small converter for the markdown the report writes, not
//! a general one.

/// The report page's stylesheet: a readable column, tables with lines whose cells wrap long
/// values, charts two per row at half the column, the table of contents in a box.
const REPORT_CSS: &str = "body{font-family:system-ui,sans-serif;max-width:1400px;\
margin:auto;padding:0 1em;color:#222;line-height:1.45}h1{border-bottom:2px solid #345}\
h2{margin-top:2em;border-bottom:1px solid #ccc}table{border-collapse:collapse;margin:0.5em 0}\
td,th{border:1px solid #bbb;padding:3px 8px;vertical-align:top;overflow-wrap:break-word}\
tr:nth-child(even){background:#f4f6f8}img{width:calc(50% - 16px);height:auto;margin:4px;\
vertical-align:top}code{font-family:ui-monospace,monospace;font-size:0.92em;\
background:#eef1f4;padding:0 3px;border-radius:3px;overflow-wrap:anywhere}\
nav.toc{background:#f4f6f8;border:1px solid #ccd;padding:0.5em 1em;display:inline-block}";

/// Text escaped for HTML (element text and attribute values).
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Where `pattern` first occurs in `s` outside code spans (`` `...` ``).
fn find_outside_code(s: &str, pattern: &str) -> Option<usize> {
    let mut i = 0;
    while i < s.len() {
        let rest = &s[i..];
        if rest.starts_with(pattern) {
            return Some(i);
        }
        if let Some(end) = rest.strip_prefix('`').and_then(|after| after.find('`')) {
            i += end + 2;
            continue;
        }
        i += rest.chars().next().map_or(1, char::len_utf8);
    }
    None
}

/// A link or image at the start of `s` (`[text](href)`, after the `!` of an image): its text,
/// its target and the length it takes.
fn link_at(s: &str) -> Option<(&str, &str, usize)> {
    let close = s.find("](")?;
    let paren = s[close + 2..].find(')')? + close + 2;
    Some((&s[1..close], &s[close + 2..paren], paren + 1))
}

/// One line's inline markdown as HTML: code spans (their text literal), images, links, bold;
/// a `*` or backtick that opens nothing stays as it is.
fn inline(s: &str) -> String {
    let mut out = String::new();
    let mut i = 0;
    while i < s.len() {
        let rest = &s[i..];
        if let Some(after) = rest.strip_prefix('`') {
            if let Some(end) = after.find('`').filter(|&e| e > 0) {
                out.push_str(&format!("<code>{}</code>", esc(&after[..end])));
                i += end + 2;
                continue;
            }
        } else if let Some(after) = rest.strip_prefix("**") {
            if let Some(end) = find_outside_code(after, "**").filter(|&e| e > 0) {
                out.push_str(&format!("<strong>{}</strong>", inline(&after[..end])));
                i += end + 4;
                continue;
            }
        } else if rest.starts_with("![") {
            if let Some((alt, src, len)) = link_at(&rest[1..]) {
                out.push_str(&format!("<img src=\"{}\" alt=\"{}\">", esc(src), esc(alt)));
                i += len + 1;
                continue;
            }
        } else if rest.starts_with('[') {
            if let Some((text, href, len)) = link_at(rest) {
                out.push_str(&format!("<a href=\"{}\">{}</a>", esc(href), inline(text)));
                i += len;
                continue;
            }
        }
        // Plain text up to the next character that may open something.
        let next = rest
            .char_indices()
            .skip(1)
            .find(|(_, c)| matches!(c, '`' | '*' | '!' | '['))
            .map_or(rest.len(), |(k, _)| k);
        out.push_str(&esc(&rest[..next]));
        i += next;
    }
    out
}

/// A table row's cells: split at bars that are not escaped (`\|` is a bar in the text).
fn cells(row: &str) -> Vec<String> {
    let row = row.trim();
    let row = row.strip_prefix('|').unwrap_or(row);
    let row = row
        .strip_suffix('|')
        .filter(|r| !r.ends_with('\\'))
        .unwrap_or(row);
    let (mut out, mut cell) = (Vec::new(), String::new());
    let mut chars = row.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                cell.push('|');
                chars.next();
            }
            '|' => out.push(std::mem::take(&mut cell).trim().to_string()),
            c => cell.push(c),
        }
    }
    out.push(cell.trim().to_string());
    out
}

/// The report's markdown as an HTML page titled `title`.
pub fn markdown_to_html(title: &str, md: &str) -> String {
    let mut html = format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{}</title><style>{REPORT_CSS}</style></head><body>\n",
        esc(title)
    );
    // A table of contents of the sections (## headings), placed after the title.
    let sections: Vec<&str> = md.lines().filter_map(|l| l.strip_prefix("## ")).collect();
    let mut toc = String::from("<nav class=\"toc\"><b>Contents</b><ol>\n");
    for (k, h) in sections.iter().enumerate() {
        toc.push_str(&format!(
            "<li><a href=\"#section-{k}\">{}</a></li>\n",
            inline(h)
        ));
    }
    toc.push_str("</ol></nav>\n");
    let mut section_index = 0;
    // The open block: "table", "ul" or "p".
    let mut open: Option<&str> = None;
    let close = |html: &mut String, open: &mut Option<&str>| {
        if let Some(tag) = open.take() {
            html.push_str(&format!("</{tag}>\n"));
        }
    };
    for line in md.lines() {
        let l = line.trim_end();
        let block = if l.starts_with('|') {
            Some("table")
        } else if l.starts_with("- ") {
            Some("ul")
        } else if l.is_empty() || ["# ", "## ", "### "].iter().any(|h| l.starts_with(h)) {
            None
        } else {
            Some("p")
        };
        if block != open {
            close(&mut html, &mut open);
            if let Some(tag) = block {
                html.push_str(&format!("<{tag}>"));
                html.push_str(if tag == "p" { "" } else { "\n" });
                open = Some(tag);
            }
        } else if block == Some("p") {
            html.push('\n');
        }
        if block == Some("table") {
            // The separator row under the header says nothing to a reader.
            if l.contains("---") && l.chars().all(|c| matches!(c, '|' | '-' | ':' | ' ')) {
                continue;
            }
            html.push_str("<tr>");
            for c in cells(l) {
                html.push_str(&format!("<td>{}</td>", inline(&c)));
            }
            html.push_str("</tr>\n");
        } else if let Some(item) = l.strip_prefix("- ") {
            html.push_str(&format!("<li>{}</li>\n", inline(item)));
        } else if block == Some("p") {
            html.push_str(&inline(l));
        } else if let Some(h) = l.strip_prefix("### ") {
            html.push_str(&format!("<h3>{}</h3>\n", inline(h)));
        } else if let Some(h) = l.strip_prefix("## ") {
            html.push_str(&format!(
                "<h2 id=\"section-{section_index}\">{}</h2>\n",
                inline(h)
            ));
            section_index += 1;
        } else if let Some(h) = l.strip_prefix("# ") {
            html.push_str(&format!("<h1>{}</h1>\n", inline(h)));
            if !sections.is_empty() {
                html.push_str(&toc);
                toc.clear();
            }
        }
    }
    close(&mut html, &mut open);
    html.push_str("</body></html>\n");
    html
}

#[cfg(test)]
mod tests {
    use super::{inline, markdown_to_html};

    #[test]
    fn bold_and_code_are_rendered_and_escaped() {
        assert_eq!(
            inline("a **cannot be judged**: `ring.csv`"),
            "a <strong>cannot be judged</strong>: <code>ring.csv</code>"
        );
        // Code keeps its text literal and escaped: markup inside it is not markup.
        assert_eq!(inline("`a<b & **c**`"), "<code>a&lt;b &amp; **c**</code>");
        assert_eq!(
            inline("**`x` bold**"),
            "<strong><code>x</code> bold</strong>"
        );
        // A `**` inside code does not close the bold around it.
        assert_eq!(
            inline("**see `a**b` here**"),
            "<strong>see <code>a**b</code> here</strong>"
        );
        // A lone `*`, a `**` that closes nothing and a lone backtick stay as they are.
        assert_eq!(inline("2 * 3 = 6"), "2 * 3 = 6");
        assert_eq!(inline("x ** y"), "x ** y");
        assert_eq!(inline("it`s"), "it`s");
        assert_eq!(inline("a < b"), "a &lt; b");
        // Links and images as before, their text and targets escaped.
        assert_eq!(
            inline("![alt \"q\"](a.png) [**t**](#s)"),
            "<img src=\"a.png\" alt=\"alt &quot;q&quot;\"> <a href=\"#s\"><strong>t</strong></a>"
        );
        assert_eq!(inline("[not a link"), "[not a link");
    }

    #[test]
    fn cells_items_headings_and_paragraphs_render_inline_markdown() {
        let md = "# T `x`\n\n## S **b**\n\n| a | `c\\|d` |\n|---|---|\n| **1** | 2 |\n\n\
                  - `run`: **no**\n\n![a](a.png)\n![b](b.png)\n\ntext 2 * 3\nmore\n";
        let html = markdown_to_html("t", md);
        assert!(html.contains("<h1>T <code>x</code></h1>"), "{html}");
        assert!(
            html.contains("<h2 id=\"section-0\">S <strong>b</strong></h2>"),
            "{html}"
        );
        assert!(
            html.contains("<a href=\"#section-0\">S <strong>b</strong></a>"),
            "{html}"
        );
        assert!(html.contains("<td><code>c|d</code></td>"), "{html}");
        assert!(html.contains("<td><strong>1</strong></td>"), "{html}");
        assert!(!html.contains("---"), "{html}");
        assert!(
            html.contains("<li><code>run</code>: <strong>no</strong></li>"),
            "{html}"
        );
        // Consecutive lines are one paragraph: the two charts stand side by side.
        assert!(
            html.contains("<p><img src=\"a.png\" alt=\"a\">\n<img src=\"b.png\" alt=\"b\"></p>"),
            "{html}"
        );
        assert!(html.contains("<p>text 2 * 3\nmore</p>"), "{html}");
        let body = &html[html.find("<body>").unwrap()..];
        assert!(!body.contains("**") && !body.contains('`'), "{body}");
    }
}
