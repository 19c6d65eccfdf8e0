//! Undeformed gap of the S1002 wheel on the 1:40 54E1 rail across the head, for a tape-circle
//! position: `g(y) = max(h) - h(y)`, `h = rail height + wheel radius increment` (the gap Kalker's
//! `--profile-gap` solves on, at x = 0). For checking a meshed contact against the profiles.
//!
//! `cargo run --release --example profile_gap -- [WHEEL_Y_M] [STEP_MM]`
use squeal::kalker::profiles::{rail_top_height_m, s1002_on_54e1, wheel_radius_offset_m};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let wheel_y_m: f64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(0.0);
    let step_mm: f64 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(0.5);
    let contact = match s1002_on_54e1(wheel_y_m, 0.46) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let height = |y: f64| rail_top_height_m(y).map(|z| z + wheel_radius_offset_m(y, wheel_y_m));
    let top = height(contact.contact_y_m).unwrap_or(f64::NAN);
    println!(
        "# tape circle at y = {wheel_y_m} m; first contact at y = {:.2} mm",
        contact.contact_y_m * 1e3
    );
    println!("y_mm,gap_um,rail_height_um,wheel_radius_increment_um");
    let mut y_mm = -35.0;
    while y_mm <= 35.0 {
        if let Some(h) = height(y_mm * 1e-3) {
            let rail_m = rail_top_height_m(y_mm * 1e-3).unwrap_or(f64::NAN);
            println!(
                "{y_mm:.2},{:.1},{:.1},{:.1}",
                (top - h) * 1e6,
                rail_m * 1e6,
                wheel_radius_offset_m(y_mm * 1e-3, wheel_y_m) * 1e6
            );
        }
        y_mm += step_mm;
    }
}
