//! Reading JSON input files with errors that name the file and the field (serde_path_to_error
//! gives the full path of an unknown, missing or mistyped field).

use std::path::Path;

use serde::de::DeserializeOwned;

use crate::{Error, Result};

/// Parse JSON text; `source_name` (a path or "embedded default") is used in error messages.
/// Unknown, missing or mistyped fields are reported with their full path (e.g. `web.thickness_at_rim_mm`).
pub fn parse_json<T: DeserializeOwned>(text: &str, source_name: &str) -> Result<T> {
    let de = &mut serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let field = if path.is_empty() || path == "." {
            "(document)".to_string()
        } else {
            path
        };
        Error::input(source_name, field, format!("{inner}"))
    })
}

/// Read and parse a JSON file.
pub fn read_json<T: DeserializeOwned>(path: &Path) -> Result<T> {
    let text = read_text(path)?;
    parse_json(&text, &path.display().to_string())
}

/// The text of a JSON input file and its untyped value, to tell which kind of file it is
/// before the typed parse (a malformed file gives `Null` here; the typed parse of the text
/// then reports it with its line and field).
pub fn read_json_kind(path: &Path) -> Result<(String, serde_json::Value)> {
    let text = read_text(path)?;
    let value = serde_json::from_str(&text).unwrap_or_default();
    Ok((text, value))
}

/// The text of an input file; a path that names no file is an input error (exit 2).
pub fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path).map_err(|e| {
        // A path that names no file is a mistake in the input (exit 2), not a failing disk.
        if e.kind() == std::io::ErrorKind::NotFound {
            Error::input(
                path.display().to_string(),
                "file",
                "does not exist: expected an existing JSON file (check the path)",
            )
        } else {
            Error::reading(path, e)
        }
    })
}
