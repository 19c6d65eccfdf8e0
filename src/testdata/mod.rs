//! Test data: what a laboratory measures on a wheel and how it is compared with the FE modes.
//!
//! - [`uff`]: the Universal File Format (datasets 15, 55, 58/58b, 164, 2411), read and written
//!   as the test systems write it.
//! - [`ema`]: experimental modal analysis of measured FRFs (LSCF with a stabilisation diagram,
//!   LSFD residues, peak picking), the modes of a test stored in a universal file, MAC and the
//!   pairing of test modes with FE modes.
//! - [`hammer`]: hammer-test natural frequencies from a CSV table, compared with FE modes.

pub mod ema;
pub mod hammer;
pub mod uff;
