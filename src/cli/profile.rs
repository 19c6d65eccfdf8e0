//! `squeal profile`: the standard profiles as point tables.

use clap::{Args, ValueEnum};
use squeal::geometry::{curve2d::polygon_properties, rail54e1, s1002};
use squeal::{Error, Result};

/// Which profile.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ProfileName {
    /// S1002 wheel tread (EN 13715): columns s_mm, f_mm (radius increment).
    S1002,
    /// 54E1 rail section (EN 13674-1), closed outline: columns y_mm, z_mm.
    #[value(name = "54e1")]
    Rail54e1,
}

/// Arguments of `squeal profile`.
#[derive(Args, Debug)]
pub struct ProfileArgs {
    /// Profile name.
    pub name: ProfileName,
    /// Print the point table as CSV (default: a short summary).
    #[arg(long)]
    pub csv: bool,
    /// Point spacing (mm), in (0.001, 50].
    #[arg(long, default_value_t = 0.5)]
    pub step_mm: f64,
    /// For 54E1: apply the 1:40 inclination (top towards the track centre, -y).
    #[arg(long)]
    pub inclined: bool,
}

/// Run `squeal profile`.
pub fn run(args: ProfileArgs) -> Result<()> {
    if !(args.step_mm > 0.001 && args.step_mm <= 50.0) {
        return Err(Error::input(
            "command line",
            "--step-mm",
            format!("must be in (0.001, 50], got {}", args.step_mm),
        ));
    }
    match args.name {
        ProfileName::S1002 => {
            let table = s1002::point_table(args.step_mm);
            if args.csv {
                println!("s_mm,f_mm");
                for (s, f) in table {
                    println!("{s:.6},{f:.6}");
                }
            } else {
                println!(
                    "S1002: {} points from S = {} to {} mm",
                    table.len(),
                    s1002::S_FLANGE_BACK_MM,
                    s1002::S_FIELD_FACE_MM
                );
                println!(
                    "flange height {:.3} mm, flange thickness {:.3} mm, qR {:.3} mm",
                    s1002::flange_height_mm(),
                    s1002::flange_thickness_mm(),
                    s1002::qr_mm()
                );
            }
        }
        ProfileName::Rail54e1 => {
            let pts = rail54e1::outline_points(args.step_mm);
            let (s, c) = if args.inclined {
                rail54e1::INCLINATION_RAD.sin_cos()
            } else {
                (0.0, 1.0)
            };
            if args.csv {
                println!("y_mm,z_mm");
                for p in &pts {
                    println!("{:.6},{:.6}", p[0] * c - p[1] * s, p[0] * s + p[1] * c);
                }
            } else {
                let (area, centroid, i_h, i_v) = polygon_properties(&pts);
                println!(
                    "54E1: {} outline points; area {:.2} cm^2, centroid z {:.2} mm",
                    pts.len(),
                    area / 100.0,
                    centroid[1]
                );
                println!(
                    "I about horizontal axis {:.1} cm^4, about vertical axis {:.1} cm^4",
                    i_h / 1e4,
                    i_v / 1e4
                );
            }
        }
    }
    Ok(())
}
