//! Squeal stability: complex eigenvalues of the rolling wheel-rail system linearised at an
//! operating point.
//!
//! The frequency-domain (complex-eigenvalue) route of curve-squeal research: the wheel as a
//! modal model from the axisymmetric solver ([`wheel`]), the rail as a fitted modal model of a
//! Timoshenko beam on discrete supports ([`rail`], [`rail_fit`]), joined at the contact by the
//! Hertz spring and the creep forces linearised about the operating point ([`contact`]); the
//! coupled system's state matrix and its eigenvalues ([`system`]). An eigenvalue with a positive
//! real part is an unstable (growing) vibration: by mode coupling where the friction force
//! follows the normal force (Hoffmann, Fischer, Begout, Gaul, "A minimal model for studying
//! properties of the mode-coupling type instability in friction induced oscillations", Mech.
//! Res. Commun. 29 (2002) 197-205), by a negative slope where the friction falls with the
//! slip speed (Heckl & Abrahams, "Curve squeal of train wheels, part 1", J. Sound Vib. 229
//! (2000) 669-693), both together as in Ding, Squicciarini, Thompson, Corradi, "An assessment
//! of mode-coupling and falling-friction mechanisms in railway curve squeal through a
//! simplified approach", J. Sound Vib. 423 (2018) 126-140; the contact's lateral position
//! couples the wheel's axial and radial motion (de Beer, Janssens, Kooijman, J. Sound Vib. 267
//! (2003) 497-507). docs/stability.md states the method, its checks and what is left out.

pub mod banded;
pub mod bench;
pub mod contact;
pub mod model;
pub mod operating;
pub mod output;
pub mod rail;
pub mod rail_fe;
pub mod rail_modes;
pub mod sweep;
pub mod system;
pub mod wheel;
