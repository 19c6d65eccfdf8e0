//! Geometry: standard profiles (S1002 wheel, EN 13715; 54E1 rail, EN 13674-1) and plane curves
//! (lines, arcs, fillets, section properties). The wheel section a wheel file describes is
//! [`crate::input::wheel`]; the track layout is [`crate::mesh::track`].

pub mod curve2d;
pub mod rail54e1;
pub mod s1002;
