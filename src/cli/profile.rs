//! `squeal profile`: the standard profiles as point tables.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use squeal::geometry::{curve2d::polygon_properties, rail54e1, s1002};
use squeal::kalker::profiles;
use squeal::kalker::rolling::DEFAULT_WHEEL_RADIUS_M;
use squeal::{Error, Result};

use super::grammar::note;

/// Where the point table goes: nowhere (a summary is printed), standard output, or a file.
enum TableTarget {
    Summary,
    Stdout,
    File(PathBuf),
}

impl TableTarget {
    fn of(csv: &Option<Option<PathBuf>>) -> TableTarget {
        match csv {
            None => TableTarget::Summary,
            Some(None) => {
                note(
                    "--csv (no value)",
                    "--csv - (standard output) or --csv FILE",
                );
                TableTarget::Stdout
            }
            Some(Some(p)) if p.as_os_str() == "-" => TableTarget::Stdout,
            Some(Some(p)) => TableTarget::File(p.clone()),
        }
    }

    /// Emit a CSV table; returns whether the summary should still be printed.
    fn emit(&self, table: &str) -> Result<bool> {
        match self {
            TableTarget::Summary => Ok(true),
            TableTarget::Stdout => {
                print!("{table}");
                Ok(false)
            }
            TableTarget::File(path) => {
                squeal::output::write_file_staged(path, |p| {
                    std::fs::write(p, table).map_err(|e| Error::io(p, e))
                })?;
                println!("wrote {}", path.display());
                Ok(true)
            }
        }
    }
}

/// Which profile.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ProfileName {
    /// S1002 wheel tread (EN 13715): columns s_mm, f_mm (radius increment).
    S1002,
    /// 54E1 rail section (EN 13674-1), closed outline: columns y_mm, z_mm.
    #[value(name = "54e1")]
    Rail54e1,
    /// S1002 on the inclined 54E1 as the wheel moves sideways (--from-mm .. --to-mm): columns
    /// wheel_y_mm, contact_y_mm, curvature_x_per_m, curvature_y_per_m (where Hertz applies:
    /// a contact point and curvatures that change little).
    Contact,
    /// The undeformed gap across the rail head for the tape circle at --wheel-y-mm: columns
    /// y_mm, gap_um, rail_height_um, wheel_radius_increment_um.
    Gap,
}

/// Arguments of `squeal profile`.
#[derive(Args, Debug)]
pub struct ProfileArgs {
    /// Profile name.
    pub name: ProfileName,
    /// Also write the point table as CSV to this file (`-`: standard output, instead of the
    /// summary). `contact` and `gap` print their table anyway.
    #[arg(long, num_args = 0..=1)]
    pub csv: Option<Option<PathBuf>>,
    /// Point spacing (mm), in (0.001, 50].
    #[arg(long, default_value_t = profiles::DEFAULT_TABLE_STEP_MM)]
    pub step_mm: f64,
    /// For 54E1: apply the 1:40 inclination (top towards the track centre, -y).
    #[arg(long)]
    pub inclined: bool,
    /// For `contact`: first tape-circle position (mm from the rail centre), in [-30, 30].
    #[arg(long, default_value_t = profiles::DEFAULT_CONTACT_SCAN_MM.0, allow_negative_numbers = true)]
    pub from_mm: f64,
    /// For `contact`: last tape-circle position (mm), in [-30, 30] and >= --from-mm.
    #[arg(long, default_value_t = profiles::DEFAULT_CONTACT_SCAN_MM.1, allow_negative_numbers = true)]
    pub to_mm: f64,
    /// For `gap`: tape-circle position (mm from the rail centre), in [-30, 30].
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub wheel_y_mm: f64,
    /// For `contact` and `gap`: wheel rolling radius (m), in [0.2, 0.7].
    #[arg(long, default_value_t = DEFAULT_WHEEL_RADIUS_M)]
    pub wheel_radius_m: f64,
    /// For 54E1: element size (mm) of the section mesh on which the torsion constant, shear
    /// centre and warping constant are solved, in [0.5, 10].
    #[arg(long, default_value_t = profiles::DEFAULT_SECTION_ELEMENT_MM)]
    pub section_mm: f64,
}

fn in_range(field: &str, value: f64, lo: f64, hi: f64) -> Result<()> {
    if value >= lo && value <= hi {
        Ok(())
    } else {
        Err(Error::input(
            "command line",
            field,
            format!("must be in [{lo}, {hi}], got {value}"),
        ))
    }
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
    if matches!(args.name, ProfileName::Contact | ProfileName::Gap) {
        in_range("--wheel-radius-m", args.wheel_radius_m, 0.2, 0.7)?;
        in_range("--from-mm", args.from_mm, -30.0, 30.0)?;
        in_range("--to-mm", args.to_mm, args.from_mm, 30.0)?;
        in_range("--wheel-y-mm", args.wheel_y_mm, -30.0, 30.0)?;
    }
    let target = TableTarget::of(&args.csv);
    match args.name {
        ProfileName::Contact => {
            let mut table =
                String::from("wheel_y_mm,contact_y_mm,curvature_x_per_m,curvature_y_per_m\n");
            let count = ((args.to_mm - args.from_mm) / args.step_mm + 1e-9).floor() as usize;
            for i in 0..=count {
                let y_mm = args.from_mm + i as f64 * args.step_mm;
                match profiles::s1002_on_54e1(y_mm * 1e-3, args.wheel_radius_m) {
                    Ok(c) => {
                        let _ = writeln!(
                            table,
                            "{y_mm:.3},{:.3},{:.4},{:.4}",
                            c.contact_y_m * 1e3,
                            c.curvature_x_per_m,
                            c.curvature_y_per_m
                        );
                    }
                    // A position without a single contact point: said, and the scan goes on.
                    Err(e) => eprintln!("wheel_y {y_mm:.3} mm: {e}"),
                }
            }
            if target.emit(&table)? {
                print!("{table}");
            }
        }
        ProfileName::Gap => {
            let (contact, rows) = profiles::undeformed_gap_across_head(
                args.wheel_y_mm * 1e-3,
                args.wheel_radius_m,
                args.step_mm * 1e-3,
            )?;
            let mut table = format!(
                "# tape circle at y = {} mm; first contact at y = {:.2} mm\n",
                args.wheel_y_mm,
                contact.contact_y_m * 1e3
            );
            table.push_str("y_mm,gap_um,rail_height_um,wheel_radius_increment_um\n");
            for r in rows {
                let _ = writeln!(
                    table,
                    "{:.3},{:.1},{:.1},{:.1}",
                    r.y_m * 1e3,
                    r.gap_m * 1e6,
                    r.rail_height_m * 1e6,
                    r.wheel_radius_increment_m * 1e6
                );
            }
            if target.emit(&table)? {
                print!("{table}");
            }
        }
        ProfileName::S1002 => {
            let table = s1002::point_table(args.step_mm);
            let mut csv = String::from("s_mm,f_mm\n");
            for (s, f) in &table {
                let _ = writeln!(csv, "{s:.6},{f:.6}");
            }
            if target.emit(&csv)? {
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
            in_range("--section-mm", args.section_mm, 0.5, 10.0)?;
            let pts = rail54e1::outline_points(args.step_mm);
            let (s, c) = if args.inclined {
                rail54e1::INCLINATION_RAD.sin_cos()
            } else {
                (0.0, 1.0)
            };
            let mut csv = String::from("y_mm,z_mm\n");
            for p in &pts {
                let _ = writeln!(csv, "{:.6},{:.6}", p[0] * c - p[1] * s, p[0] * s + p[1] * c);
            }
            if target.emit(&csv)? {
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
                let mesh = squeal::mesh::rail::rail_section(squeal::mesh::rail::RailSectionSizes {
                    running_surface_mm: args.section_mm,
                    body_mm: args.section_mm,
                    band_rows_at_least: 1,
                });
                let p = squeal::fem::section_properties::section_properties(&mesh.body)?;
                println!(
                    "section mesh ({} quads of {} mm): area {:.2} cm^2; Saint-Venant torsion \
                     constant J {:.1} cm^4, shear centre z {:.2} mm (centroid {:.2} mm), warping \
                     constant {:.0} cm^6 (docs/stability.md)",
                    mesh.body.quads.len(),
                    args.section_mm,
                    p.area / 100.0,
                    p.torsion_constant / 1e4,
                    p.shear_centre[1],
                    p.centroid[1],
                    p.warping_constant / 1e6
                );
            }
        }
    }
    Ok(())
}
