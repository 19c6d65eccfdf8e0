//! Where S1002 touches 54E1 (at 1:40) as the wheel moves sideways, and the Hertz curvatures
//! there: the table used to place the wheel of the static Hertz check
//! (`data/scenarios/hertz-1mm.json`) so that its patch lies inside one arc of the rail crown.
//!
//!     cargo run --release --example scan_y -- [from_mm] [to_mm] [step_mm]
//!
//! Defaults: -30 to 24 mm in 1 mm steps, wheel radius 0.46 m. A contact point that moves little
//! as the wheel moves, with curvatures that change little, is where Hertz applies.

fn main() {
    let arg = |i: usize, default: f64| {
        std::env::args()
            .nth(i)
            .and_then(|s| s.parse::<f64>().ok())
            .unwrap_or(default)
    };
    let (from_mm, to_mm, step_mm) = (arg(1, -30.0), arg(2, 24.0), arg(3, 1.0).max(0.01));
    println!("wheel_y_mm,contact_y_mm,curvature_x_per_m,curvature_y_per_m");
    let mut y_mm = from_mm;
    while y_mm <= to_mm + 1e-9 {
        match squeal::kalker::profiles::s1002_on_54e1(y_mm * 1e-3, 0.46) {
            Ok(c) => println!(
                "{y_mm:.2},{:.3},{:.4},{:.4}",
                c.contact_y_m * 1e3,
                c.curvature_x_per_m,
                c.curvature_y_per_m
            ),
            Err(e) => eprintln!("wheel_y {y_mm:.2} mm: {e}"),
        }
        y_mm += step_mm;
    }
}
