//! Subcommand argument types and their glue to the library, one file per subcommand.
pub mod kalker;
