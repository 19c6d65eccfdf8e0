//! Geometry: standard profiles (S1002 wheel, 54E1 rail), plane curves, the wheel
//! cross-section and the track layout.

pub mod curve2d;
pub mod rail54e1;
pub mod s1002;
pub mod wheel;
