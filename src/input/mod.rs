//! Input files: reading them and checking every field, with one error format ([`Error::Input`]:
//! the file, the field's full path, the allowed range; exit status 2).
//!
//! - [`json`]: JSON files read into serde types, with the path of a bad field.
//! - [`checker`]: [`Checker`], the one validation style (`positive`, `within`, `require`).
//! - [`wheel`]: the wheel file (`data/wheels/*.json`), its checks and the section it describes
//!   (tread radius, web, axle).
//!
//! The model file (`data/models/*.json`, [`crate::scenario`]) and the case file
//! (`data/cases/*.json`, [`crate::model::case`]) use the same two pieces; they sit above the
//! mesh stage because their fields are the mesher's and the engine's own settings.
//!
//! [`Error::Input`]: crate::Error::Input

pub mod checker;
pub mod json;
pub mod wheel;

pub use checker::Checker;
pub use json::{parse_json, read_json, read_json_kind, read_text};
