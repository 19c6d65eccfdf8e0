//! ParaView data collection (`.pvd`): a list of `.vtu` files with their times, which ParaView
//! opens as one time series (its animation controls step through the files).
//!
//! Format (VTK file formats, "ParaView Data"): `<VTKFile type="Collection">` holding one
//! `<DataSet timestep=".." part="0" file=".."/>` per file; file names are relative to the
//! `.pvd` file.

use std::path::Path;

use crate::{Error, Result};

/// Writes `path` listing `(time_s, file name)` in ascending time.
pub fn write_collection(path: &Path, entries: &[(f64, String)]) -> Result<()> {
    let mut sorted: Vec<&(f64, String)> = entries.iter().collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut text = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
         byte_order=\"LittleEndian\">\n  <Collection>\n",
    );
    for (time_s, file) in sorted {
        let escaped = file
            .replace('&', "&amp;")
            .replace('"', "&quot;")
            .replace('<', "&lt;");
        text.push_str(&format!(
            "    <DataSet timestep=\"{time_s:.9e}\" part=\"0\" file=\"{escaped}\"/>\n"
        ));
    }
    text.push_str("  </Collection>\n</VTKFile>\n");
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}

/// Reads the `(time_s, file)` entries of a collection written by [`write_collection`].
pub fn read_collection(path: &Path) -> Result<Vec<(f64, String)>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::reading(path, e))?;
    let source = path.display().to_string();
    let attribute = |line: &str, name: &str| -> Option<String> {
        let start = line.find(&format!("{name}=\""))? + name.len() + 2;
        let end = line[start..].find('"')? + start;
        Some(line[start..end].to_string())
    };
    let mut out = Vec::new();
    for (k, line) in text.lines().enumerate() {
        if !line.trim_start().starts_with("<DataSet") {
            continue;
        }
        let bad = || {
            Error::input(
                &source,
                format!("line {}", k + 1),
                "a DataSet needs timestep and file",
            )
        };
        let time: f64 = attribute(line, "timestep")
            .and_then(|t| t.parse().ok())
            .ok_or_else(bad)?;
        let file = attribute(line, "file").ok_or_else(bad)?;
        out.push((time, file));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collection_round_trips_in_time_order() {
        let dir = std::env::temp_dir().join(format!("squeal_pvd_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("run.pvd");
        let entries = vec![(2e-3, "b.vtu".to_string()), (1e-3, "a.vtu".to_string())];
        write_collection(&path, &entries).unwrap();
        let back = read_collection(&path).unwrap();
        assert_eq!(
            back,
            vec![(1e-3, "a.vtu".to_string()), (2e-3, "b.vtu".to_string())]
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
