//! `squeal mesh`: build the wheel or the whole model mesh, print its quality, write VTU / MSH.

use std::path::{Path, PathBuf};

use clap::Args;
use squeal::input::wheel::WheelSpec;
use squeal::mesh::quality::dilatational_wave_speed;
use squeal::mesh::wheel::{wheel_mesh, WheelPlacement};
use squeal::mesh::{gmsh, vtu, Mesh};
use squeal::output::write_file_staged;
use squeal::scenario::LoadedScenario;
use squeal::{Error, Result};

use super::grammar::{input_name, note, out_dir};

/// Arguments of `squeal mesh`.
#[derive(Args, Debug)]
#[command(group(clap::ArgGroup::new("input").required(true).args(["model", "wheel"])))]
pub struct MeshArgs {
    /// Model file (wheel + track), e.g. data/models/demo.json.
    #[arg(long, alias = "scenario")]
    pub model: Option<PathBuf>,
    /// Wheel file only (wheel and half axle), e.g. data/wheels/ns_intercity_920.json.
    #[arg(long)]
    pub wheel: Option<PathBuf>,
    /// Folder for mesh.vtu (ParaView) and quality.json. Default: out/mesh/<model or wheel
    /// name>.
    #[arg(long)]
    pub out: Vec<PathBuf>,
    /// Also write the mesh as VTU (ParaView) to this file.
    #[arg(long)]
    pub vtu: Option<PathBuf>,
    /// Also write the mesh as Gmsh MSH 4.1 to this file.
    #[arg(long)]
    pub msh: Option<PathBuf>,
    /// Also write the quality report as JSON to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
}

/// Where `squeal mesh` writes: the output folder (None with the deprecated file form of
/// `--out`) and the single files, each with its format's extension checked.
struct MeshOutputs {
    dir: Option<PathBuf>,
    vtu: Vec<PathBuf>,
    msh: Vec<PathBuf>,
}

impl MeshOutputs {
    fn of(args: &MeshArgs) -> Result<MeshOutputs> {
        let extension = |p: &Path| p.extension().and_then(|e| e.to_str()).map(str::to_string);
        let check = |p: &Path, option: &str, wanted: &str| -> Result<()> {
            if extension(p).as_deref() == Some(wanted) {
                Ok(())
            } else {
                Err(Error::input(
                    "command line",
                    option,
                    format!("`{}`: the extension must be .{wanted}", p.display()),
                ))
            }
        };
        let mut outputs = MeshOutputs {
            dir: None,
            vtu: args.vtu.iter().cloned().collect(),
            msh: args.msh.iter().cloned().collect(),
        };
        for p in &outputs.vtu {
            check(p, "--vtu", "vtu")?;
        }
        for p in &outputs.msh {
            check(p, "--msh", "msh")?;
        }
        // The previous release took mesh files in --out (repeatable): still accepted, with
        // the note; any other --out value is the output folder, given once.
        let mut dirs = Vec::new();
        for p in &args.out {
            match extension(p).as_deref() {
                Some("vtu") => {
                    note("--out FILE.vtu", "--vtu FILE.vtu (or --out DIR)");
                    outputs.vtu.push(p.clone());
                }
                Some("msh") => {
                    note("--out FILE.msh", "--msh FILE.msh (or --out DIR)");
                    outputs.msh.push(p.clone());
                }
                _ => dirs.push(p.clone()),
            }
        }
        if dirs.len() > 1 {
            return Err(Error::input(
                "command line",
                "--out",
                "give one output folder (mesh files: --vtu FILE, --msh FILE)",
            ));
        }
        let deprecated_files = dirs.is_empty() && !args.out.is_empty();
        if !deprecated_files {
            let input = args.model.as_ref().or(args.wheel.as_ref());
            let name = input.map(|p| input_name(p)).unwrap_or_default();
            outputs.dir = Some(out_dir(dirs.pop(), "mesh", &name));
        }
        Ok(outputs)
    }
}

/// Mass of the elements of the given materials (kg), from their volume and density.
pub fn mass_kg(mesh: &Mesh, materials: &[u32], density_kg_per_m3: f64) -> f64 {
    mesh.volume_by_material()
        .iter()
        .filter(|(m, _)| materials.contains(m))
        .map(|(_, v)| v * density_kg_per_m3)
        .sum()
}

/// Run `squeal mesh`.
pub fn run(args: MeshArgs) -> Result<()> {
    squeal::output::protect_inputs(args.model.iter().chain(&args.wheel));
    let outputs = MeshOutputs::of(&args)?;
    let started = std::time::Instant::now();
    let (mesh, steel) = if let Some(path) = &args.model {
        let loaded = LoadedScenario::from_file(path)?;
        (loaded.model_mesh(), loaded.wheel.material)
    } else {
        let path = args.wheel.as_ref().expect("clap group requires one input");
        let spec: WheelSpec = squeal::input::read_json(path)?;
        spec.validate(&path.display().to_string())?;
        (
            wheel_mesh(&spec, None, &WheelPlacement::default()),
            spec.material,
        )
    };
    let built = started.elapsed();
    let c_l = dilatational_wave_speed(
        steel.youngs_modulus_pa,
        steel.poisson_ratio,
        steel.density_kg_per_m3,
    );
    let quality = mesh.quality(c_l);
    println!(
        "built {} elements in {:.2} s",
        mesh.element_count(),
        built.as_secs_f64()
    );
    println!("{}", quality.summary());
    print_parts(&mesh, steel.density_kg_per_m3);
    quality.check_valid()?;
    if let Some(json) = &args.json {
        write_json(json, &quality)?;
    }
    let mut files: Vec<PathBuf> = outputs.vtu.iter().chain(&outputs.msh).cloned().collect();
    if let Some(dir) = &outputs.dir {
        write_json(&dir.join("quality.json"), &quality)?;
        files.push(dir.join("mesh.vtu"));
    }
    for out in &files {
        write_mesh(&mesh, out)?;
        println!("wrote {}", out.display());
    }
    Ok(())
}

/// Print element counts, masses, sets, surfaces and ties.
pub fn print_parts(mesh: &Mesh, steel_density: f64) {
    use squeal::mesh::material;
    let wheel = mass_kg(
        mesh,
        &[material::WHEEL, material::TREAD_BAND],
        steel_density,
    );
    let axle = mass_kg(mesh, &[material::AXLE], steel_density);
    if wheel > 0.0 {
        println!(
            "wheel mass {wheel:.1} kg, half-axle mass {axle:.1} kg (steel {steel_density} kg/m^3)"
        );
    }
    let rail_m = mass_kg(mesh, &[material::RAIL, material::RAIL_BAND], steel_density);
    if rail_m > 0.0 {
        println!("rail mass {rail_m:.1} kg");
    }
    let sets: Vec<String> = mesh
        .node_sets
        .iter()
        .filter(|(k, _)| !k.chars().last().is_some_and(|c| c.is_ascii_digit()))
        .map(|(k, v)| format!("{k} ({})", v.len()))
        .collect();
    println!("node sets: {}", sets.join(", "));
    let surfaces: Vec<String> = mesh
        .surfaces
        .iter()
        .map(|(k, v)| format!("{k} ({} faces)", v.len()))
        .collect();
    println!("surfaces: {}", surfaces.join(", "));
    for t in &mesh.ties {
        println!(
            "tied interface {}: {} slave nodes, largest offset {:.3} mm",
            t.name,
            t.pairs.len(),
            t.max_gap_m() * 1e3
        );
    }
}

/// Write a JSON value to a file.
pub fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    let text = serde_json::to_string_pretty(value)
        .map_err(|e| Error::Numerical(format!("JSON encoding: {e}")))?;
    write_file_staged(path, |p| {
        std::fs::write(p, text).map_err(|e| Error::io(p, e))
    })
}

/// Write a mesh by extension (.vtu or .msh).
pub fn write_mesh(mesh: &Mesh, out: &Path) -> Result<()> {
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    // The format is chosen by the final name; the file is written beside it and renamed.
    let gmsh_format = out.extension().and_then(|e| e.to_str()) == Some("msh");
    write_file_staged(out, |p| {
        if gmsh_format {
            gmsh::write(mesh, p)
        } else {
            vtu::write(mesh, p, &[])
        }
    })
}
