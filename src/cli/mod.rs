//! Subcommand argument types and their glue to the library, one file per subcommand.

pub mod axisym;
pub mod bench;
pub mod default_run;
pub mod ema;
pub mod grammar;
pub mod growth;
pub mod hammer;
pub mod identify;
pub mod kalker;
pub mod mesh;
pub mod modes;
pub mod profile;
pub mod report;
pub mod signal;
pub mod simulate;
pub mod stability;
