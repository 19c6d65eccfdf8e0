//! S1002 wheel tread and flange profile (EN 13715), from its analytic definition.
//!
//! Lateral coordinate `S` in mm: `S = 0` at the tape circle (70 mm from the flange back),
//! `S = -70` at the flange back face, negative towards the flange. `F(S)` is the radius increment
//! in mm: `r(S) = R_nominal + F(S)`. The piecewise polynomial/arc form with the coefficients below
//! is the widely used one credited to H. Netter (DLR); see docs/references.md, section 1.
//!
//! The standard stops at `S = +60`. A 135 mm rim ends at `S = +65`: we extend the field-side
//! 1:15 line (section A) to `S = +62` and add a 3 mm x 45 degree chamfer down to `S = +65`
//! (our documented choice, `FIELD_CHAMFER_MM`).

/// Flange back face position (mm).
pub const S_FLANGE_BACK_MM: f64 = -70.0;
/// End of the standard definition on the field side (mm).
pub const S_FIELD_END_STANDARD_MM: f64 = 60.0;
/// Start of our field-side chamfer (mm).
pub const S_CHAMFER_START_MM: f64 = 62.0;
/// Size of our 45-degree field-side chamfer (mm).
pub const FIELD_CHAMFER_MM: f64 = 3.0;
/// Field-side rim face (mm): 135 mm rim width measured from the flange back.
pub const S_FIELD_FACE_MM: f64 = S_CHAMFER_START_MM + FIELD_CHAMFER_MM;
/// Lateral position of the flange tip (centre of the section G arc), mm.
pub const S_FLANGE_TIP_MM: f64 = -55.0;

/// Breakpoints between sections H|G|F|E|D|C|B|A, ascending (mm).
pub const BREAKPOINTS_MM: [f64; 7] = [
    -62.764705882,
    -49.662510381,
    -39.764473993,
    -38.426669071,
    -35.0,
    -26.0,
    32.15796,
];

// Section A: 1:15 field-side line.
const AA: f64 = 1.364323640;
const BA: f64 = 0.066666667;
// Section B: tread polynomial.
const BB: f64 = 3.358537058e-02;
const CB: f64 = 1.565681624e-03;
const DB: f64 = 2.810427944e-05;
const EB: f64 = 5.844240864e-08;
const FB: f64 = 1.562379023e-08;
const GB: f64 = 5.309217349e-15;
const HB: f64 = 5.957839843e-12;
const IB: f64 = 2.646656573e-13;
// Section C: flange root polynomial.
const AC: f64 = 4.320221063e+03;
const BC: f64 = 1.038384026e+03;
const CC: f64 = 1.065501873e+02;
const DC: f64 = 6.051367875;
const EC: f64 = 2.054332446e-01;
const FC: f64 = 4.169739389e-03;
const GC: f64 = 4.687195829e-05;
const HC: f64 = 2.252755540e-07;
// Section D: arc.
const AD: f64 = 16.446;
const BD: f64 = 13.0;
const CD: f64 = 26.210665;
// Section E: flange face line.
const AE: f64 = 93.576667419;
const BE: f64 = 2.747477419;
// Section F, G, H: arcs.
const AF: f64 = 8.834924130;
const BF: f64 = 20.0;
const CF: f64 = 58.558326413;
const AG: f64 = 16.0;
const BG: f64 = 12.0;
const CG: f64 = 55.0;
const AH: f64 = 9.519259302;
const BH: f64 = 20.5;
const CH: f64 = 49.5;

/// `sqrt(max(x, 0))`: arcs are evaluated right up to their vertical tangents, where rounding
/// could make the radicand a tiny negative number.
fn sqrt_clamped(x: f64) -> f64 {
    x.max(0.0).sqrt()
}

/// Radius increment `F(S)` (mm) of the standard S1002 definition, `S` in [-70, 60] mm.
/// Outside that range the nearest section's formula is extrapolated (callers clamp).
pub fn standard_height_mm(s_mm: f64) -> f64 {
    let s = s_mm;
    let [bh_g, bg_f, bf_e, be_d, bd_c, bc_b, bb_a] = BREAKPOINTS_MM;
    if s >= bb_a {
        AA - BA * s
    } else if s >= bc_b {
        // Horner form of AB - BB s + CB s^2 - DB s^3 + EB s^4 - FB s^5 + GB s^6 - HB s^7 + IB s^8.
        let coeffs = [0.0, -BB, CB, -DB, EB, -FB, GB, -HB, IB];
        coeffs.iter().rev().fold(0.0, |acc, c| acc * s + c)
    } else if s >= bd_c {
        let coeffs = [-AC, -BC, -CC, -DC, -EC, -FC, -GC, -HC];
        coeffs.iter().rev().fold(0.0, |acc, c| acc * s + c)
    } else if s >= be_d {
        AD - sqrt_clamped(BD * BD - (s + CD) * (s + CD))
    } else if s >= bf_e {
        -AE - BE * s
    } else if s >= bg_f {
        AF + sqrt_clamped(BF * BF - (s + CF) * (s + CF))
    } else if s >= bh_g {
        AG + sqrt_clamped(BG * BG - (s + CG) * (s + CG))
    } else {
        AH + sqrt_clamped(BH * BH - (s + CH) * (s + CH))
    }
}

/// Radius increment (mm) of the full 135 mm tread used by the toolkit: the standard profile on
/// [-70, 60], the 1:15 line extended to 62, then the 45-degree chamfer to the field face at 65.
pub fn height_mm(s_mm: f64) -> f64 {
    let s = s_mm.clamp(S_FLANGE_BACK_MM, S_FIELD_FACE_MM);
    if s <= S_CHAMFER_START_MM {
        standard_height_mm(s)
    } else {
        standard_height_mm(S_CHAMFER_START_MM) - (s - S_CHAMFER_START_MM)
    }
}

/// Lateral position (mm) where the flange face (towards the tread) has height `f_mm`, for
/// `f_mm` between the tread and the flange tip. Found by bisection on [-55, 0] where F falls
/// monotonically.
pub fn flange_face_position_mm(f_mm: f64) -> f64 {
    let (mut lo, mut hi) = (S_FLANGE_TIP_MM, 0.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if standard_height_mm(mid) > f_mm {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Flange height (mm): tip height above the tape circle.
pub fn flange_height_mm() -> f64 {
    standard_height_mm(S_FLANGE_TIP_MM)
}

/// Flange thickness Sd (mm): from the flange back to the flange face point 10 mm above the
/// tape circle (EN 15313 definition).
pub fn flange_thickness_mm() -> f64 {
    flange_face_position_mm(10.0) - S_FLANGE_BACK_MM
}

/// qR dimension (mm): lateral distance between the flange-face point 2 mm below the flange tip
/// and the flange-thickness point (EN 15313).
pub fn qr_mm() -> f64 {
    flange_face_position_mm(10.0) - flange_face_position_mm(flange_height_mm() - 2.0)
}

/// Point table of the profile: `(s_mm, f_mm)` at a given lateral step, from the flange back to
/// the field face, including all breakpoints.
pub fn point_table(step_mm: f64) -> Vec<(f64, f64)> {
    let step = step_mm.max(1e-3);
    let mut s_values: Vec<f64> = Vec::new();
    let mut s = S_FLANGE_BACK_MM;
    while s < S_FIELD_FACE_MM {
        s_values.push(s);
        s += step;
    }
    s_values.push(S_FIELD_FACE_MM);
    s_values.extend_from_slice(&BREAKPOINTS_MM);
    s_values.push(S_CHAMFER_START_MM);
    s_values.sort_by(|a, b| a.total_cmp(b));
    s_values.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    s_values.into_iter().map(|s| (s, height_mm(s))).collect()
}
