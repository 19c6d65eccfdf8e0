//! `squeal modes`: wheel natural frequencies in a band (3D hex8, incompatible modes by default,
//! `--hex8`; shift-invert Lanczos), mode classification, modes.json / modes.csv / modes.vtu,
//! optional hammer-test comparison and Matrix Market export of K and M.

use std::path::{Path, PathBuf};

use squeal::output::{Commit, StagedDir};

use clap::{Args, ValueEnum};
use squeal::fem::assembly::write_matrix_market;
use squeal::fem::Hex8Kind;
use squeal::input::wheel::WheelSpec;
use squeal::material::Material;
use squeal::mesh::vtu;
use squeal::modal::classify::ModeRecord;
use squeal::modal::pipeline::{revolved_model, solve_and_classify};
use squeal::modal::{ModalOptions, ModalSolution};
use squeal::model::modal::{mesh_model, wheel_model, Clamp};
use squeal::{Error, Result};

use super::grammar::{input_name, out_dir};

/// The axis a --mesh body's modes are labelled about (`--axis`).
#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
pub enum AxisChoice {
    /// The fitted axis of revolution (second moments of the volume; fem/axis.rs).
    Auto,
    /// The x axis through the volume centroid.
    X,
    /// The y axis.
    Y,
    /// The z axis.
    Z,
}

/// Hexahedron formulation of the stiffness (`--hex8`).
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Hex8Choice {
    /// Trilinear hex8: locks in bending (too stiff where a web is one or two elements thick).
    Standard,
    /// Wilson–Taylor incompatible modes (condensed bubbles, patch-test corrected).
    Incompatible,
}

impl From<Hex8Kind> for Hex8Choice {
    fn from(k: Hex8Kind) -> Self {
        match k {
            Hex8Kind::Standard => Hex8Choice::Standard,
            Hex8Kind::Incompatible => Hex8Choice::Incompatible,
        }
    }
}

impl From<Hex8Choice> for Hex8Kind {
    fn from(c: Hex8Choice) -> Self {
        match c {
            Hex8Choice::Standard => Hex8Kind::Standard,
            Hex8Choice::Incompatible => Hex8Kind::Incompatible,
        }
    }
}

/// Arguments of `squeal modes`.
#[derive(Args, Debug)]
#[command(group(clap::ArgGroup::new("body").required(true).args(["wheel", "mesh"])))]
pub struct ModesArgs {
    /// Wheel file, e.g. data/wheels/ns_intercity_920.json.
    #[arg(long, conflicts_with = "mesh")]
    pub wheel: Option<PathBuf>,
    /// Volume mesh instead of a wheel file: .msh (Gmsh 4.1 ASCII), .vtk (legacy ASCII) or .vtu
    /// (VTK XML), with 8-node hexahedra and 4- or 10-node tetrahedra (and, in VTK files, 27-node
    /// hexahedra, cell type 29), coordinates in metres.
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// Element size (mm), overriding the wheel file's mesh.element_size_mm.
    #[arg(long, conflicts_with = "mesh")]
    pub element_size_mm: Option<f64>,
    /// Young's modulus (Pa) of a --mesh body (default: steel, 210e9).
    #[arg(long, requires = "mesh")]
    pub youngs_modulus_pa: Option<f64>,
    /// Poisson's ratio of a --mesh body (default 0.3).
    #[arg(long, requires = "mesh")]
    pub poisson_ratio: Option<f64>,
    /// Linear tetrahedra of a --mesh: 2 elevates them to straight-sided quadratic tetrahedra
    /// (tet10: same geometry, no locking in bending), 1 keeps them linear (stiff: a warning
    /// is printed). Other elements are unaffected.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(1..=2))]
    pub element_order: u8,
    /// Density (kg/m³) of a --mesh body (default 7850).
    #[arg(long, requires = "mesh")]
    pub density_kg_per_m3: Option<f64>,
    /// Upper band edge (Hz).
    #[arg(long, default_value_t = ModalOptions::default().fmax_hz)]
    pub fmax_hz: f64,
    /// Boundary condition: `none` (free-free), `hub-bore` or `axle-ends` (named wheel node sets,
    /// --wheel only), or a box expression clamping every node inside it, e.g. "x<-1.09" or
    /// "y>=0.2, r<0.1" (x, y, z in metres, r = sqrt(x² + z²) the distance from the y axis;
    /// conditions joined by `,` or `&`).
    #[arg(long, default_value = "none")]
    pub clamp: String,
    /// Hexahedron stiffness. `incompatible` (the default): Wilson–Taylor incompatible modes,
    /// which do not lock in bending; on the wheel at 40 mm the axial (0,2)-(0,4) modes are
    /// 1.3-1.6 % above `squeal axisym` and (1,0), (1,1) 2.9 %. `standard`: the trilinear hex8,
    /// 2.5-4.1 % and 16-17 % above there. Tet10 elements are unaffected.
    #[arg(long, value_enum, default_value_t = Hex8Choice::from(Hex8Kind::default()))]
    pub hex8: Hex8Choice,
    /// Mesh the wheel as the axisymmetric solver's Q9 cross-section (`squeal axisym` at the same
    /// --element-size-mm) revolved into this many 27-node quadratic sectors, instead of the
    /// hex8 wheel mesh: the 3D model then has the very same cross-section discretisation as
    /// `squeal axisym`, and differs from it only by the circumferential interpolation (falling
    /// as (n / sectors)^4 for n nodal diameters). Allowed 3..=512; 48 keeps every mode below
    /// 5 kHz of the default wheel within 0.1 % of `squeal axisym`.
    #[arg(long, conflicts_with = "mesh")]
    pub revolved_sectors: Option<usize>,
    /// Split the band into this many slices, one shift each (spectrum slicing; 1..=32): the
    /// first shift below the spectrum, the others in the middle of their slice, each slice's
    /// completeness checked by Sturm counts at its edges. For wide bands with many modes.
    #[arg(long, default_value_t = ModalOptions::default().slices)]
    pub slices: usize,
    /// Hammer test to compare with: a CSV of labelled modes (data/hammer/), or a universal file
    /// (.uff/.unv) with FRFs (analysed by LSCF) or mode shapes, paired with the FE modes by MAC
    /// at its nodes (datasets 15/2411, in the model's axes).
    #[arg(long)]
    pub hammer: Option<PathBuf>,
    /// Output folder. Default: out/modes/<wheel or mesh name>.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write K.mtx and M.mtx (Matrix Market) to this directory.
    #[arg(long)]
    pub export_mtx: Option<PathBuf>,
    /// The axis of revolution a --mesh body's modes are labelled (m, n) about, through its
    /// volume centroid: `auto` (default) fits it from the body's second moments and warns when
    /// the body is not near-axisymmetric; `x`, `y` or `z` take that axis. A wheel file's axis
    /// is y.
    #[arg(long, value_enum)]
    pub axis: Option<AxisChoice>,
}

/// Says which axis a --mesh body's modes are labelled about, and warns when the body is not
/// near-axisymmetric about its fitted axis (the labels are then descriptive only).
fn report_axis(model: &squeal::model::modal::ModalModel, asked: bool) {
    let Some(fit) = model.axis_fit else {
        return;
    };
    let name = |a: [f64; 3]| match a {
        [1.0, 0.0, 0.0] => "x".to_string(),
        [0.0, 1.0, 0.0] => "y".to_string(),
        [0.0, 0.0, 1.0] => "z".to_string(),
        a => format!("({:.4}, {:.4}, {:.4})", a[0], a[1], a[2]),
    };
    println!(
        "modes labelled about the {} axis through the volume centroid ({}; the body's fitted \
         axis of revolution is {}, its two other second moments {:.2} % apart)",
        name(model.axis),
        if asked { "--axis" } else { "fitted" },
        name(fit.axis),
        100.0 * fit.asymmetry
    );
    if fit.asymmetry > squeal::fem::axis::ASYMMETRY_WARNING {
        eprintln!(
            "warning: the body is not near-axisymmetric ({:.1} % between the second moments \
             normal to its axis, above {:.0} %): the (m, n) labels are descriptive only",
            100.0 * fit.asymmetry,
            100.0 * squeal::fem::axis::ASYMMETRY_WARNING
        );
    }
}

/// Run `squeal modes`.
pub fn run(args: ModesArgs) -> Result<()> {
    squeal::output::protect_inputs(args.wheel.iter().chain(&args.mesh).chain(&args.hammer));
    if !(args.fmax_hz.is_finite() && args.fmax_hz > 0.0 && args.fmax_hz <= 1e6) {
        return Err(Error::input(
            "command line",
            "--fmax-hz",
            format!("{} is outside the allowed range (0, 1e6] Hz", args.fmax_hz),
        ));
    }
    squeal::modal::lanczos::check_slices(args.slices)?;
    // The material options are checked first (their ranges), then refused for a wheel, whose
    // material is its wheel file's.
    let material = mesh_material(&args)?;
    if args.wheel.is_some() {
        for (given, field) in [
            (args.youngs_modulus_pa.is_some(), "--youngs-modulus-pa"),
            (args.poisson_ratio.is_some(), "--poisson-ratio"),
            (args.density_kg_per_m3.is_some(), "--density-kg-per-m3"),
            (args.axis.is_some(), "--axis"),
        ] {
            if given {
                return Err(Error::input(
                    "command line",
                    field,
                    "applies to a --mesh body only; a wheel's material is in its wheel file \
                     (`material`)",
                ));
            }
        }
    }
    let clamp = Clamp::parse(&args.clamp)?;
    let started = std::time::Instant::now();
    let model = match &args.wheel {
        None => {
            let mut mesh = read_mesh(&args)?;
            let linear = mesh.linear_tet_count();
            if linear > 0 && args.element_order == 2 {
                let elevated = mesh.elevate_linear_tets();
                println!(
                    "element order 2: {elevated} linear tetrahedra elevated to straight-sided \
                     quadratic tetrahedra (tet10); --element-order 1 keeps them linear"
                );
            } else if linear > 0 {
                eprintln!(
                    "warning: {linear} linear tetrahedra kept linear (--element-order 1): they are \
                     stiff in bending, so frequencies come out high unless the mesh is fine; \
                     the default --element-order 2 elevates them to tet10"
                );
            }
            let axis = match args.axis.unwrap_or(AxisChoice::Auto) {
                AxisChoice::Auto => None,
                AxisChoice::X => Some(0),
                AxisChoice::Y => Some(1),
                AxisChoice::Z => Some(2),
            };
            // A mesh the elements refuse (an inverted element) is named by its file.
            let mesh_path = args.mesh.as_ref().expect("clap group: --wheel or --mesh");
            let model = mesh_model(mesh, material, &clamp, args.hex8.into(), axis).map_err(
                |e| match e {
                    Error::Mesh(m) => Error::Mesh(format!("{}: {m}", mesh_path.display())),
                    other => other,
                },
            )?;
            report_axis(&model, axis.is_some());
            if let Some(n) = model.box_clamped_nodes {
                println!("clamped {n} nodes ({})", args.clamp);
            }
            model
        }
        Some(wheel) => {
            let spec = read_wheel(wheel, args.element_size_mm)?;
            match args.revolved_sectors {
                Some(sectors) => revolved_model(&spec, &clamp, sectors, args.hex8.into())?,
                None => wheel_model(&spec, &clamp, args.hex8.into())?,
            }
        }
    };
    println!(
        "mesh: {}, {} dofs after constraints (assembled in {:.2} s)",
        model.summary,
        model.assembled.n_reduced,
        started.elapsed().as_secs_f64()
    );
    if let Some(dir) = &args.export_mtx {
        export_matrices(&model.assembled, dir)?;
    }
    let run = solve_and_classify(&model, args.fmax_hz, args.slices)?;
    print_solution(&args, &run.solution);
    // Written beside the output folder and moved into it when complete.
    let out = out_dir(
        args.out.clone(),
        "modes",
        &input_name(
            args.wheel
                .as_ref()
                .or(args.mesh.as_ref())
                .expect("clap group"),
        ),
    );
    let stage = StagedDir::new(&out)?;
    write_outputs(
        &args,
        stage.path(),
        &run.solution,
        &run.shapes,
        &run.records,
        model.node_positions_m(),
        |dir, fields| model.write_vtu(&dir.join("modes.vtu"), fields),
    )?;
    stage.commit(Commit::Merge)?;
    println!("wrote {}", out.display());
    Ok(())
}

/// Reads and checks a wheel file, with `--element-size-mm` applied.
fn read_wheel(wheel: &std::path::Path, element_size_mm: Option<f64>) -> Result<WheelSpec> {
    // An unreadable wheel file is bad input (exit code 2), named with the option.
    let mut spec: WheelSpec = squeal::input::read_json(wheel).map_err(|e| match e {
        Error::Io { path, source } => Error::input(
            path,
            "--wheel",
            format!("cannot read the wheel file ({}); expected a JSON file like data/wheels/ns_intercity_920.json", squeal::error::io_words(&source)),
        ),
        other => other,
    })?;
    if let Some(h) = element_size_mm {
        if !(h.is_finite() && (2.0..=200.0).contains(&h)) {
            return Err(Error::input(
                "command line",
                "--element-size-mm",
                format!("{h} is outside the allowed range [2, 200] mm"),
            ));
        }
        spec.mesh.element_size_mm = h;
    }
    spec.validate(&wheel.display().to_string())?;
    Ok(spec)
}

/// The material options of a --mesh body (steel by default), checked against their ranges.
fn mesh_material(args: &ModesArgs) -> Result<Material> {
    let steel = Material::STEEL;
    let nu = args.poisson_ratio.unwrap_or(steel.poisson_ratio);
    if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
        return Err(Error::input(
            "command line",
            "--poisson-ratio",
            format!("{nu} is outside the allowed range (-1, 0.5)"),
        ));
    }
    Ok(Material {
        youngs_modulus_pa: positive(
            args.youngs_modulus_pa,
            steel.youngs_modulus_pa,
            "--youngs-modulus-pa",
            1e13,
        )?,
        poisson_ratio: nu,
        density_kg_per_m3: positive(
            args.density_kg_per_m3,
            steel.density_kg_per_m3,
            "--density-kg-per-m3",
            1e6,
        )?,
    })
}

/// Reads `--mesh`.
fn read_mesh(args: &ModesArgs) -> Result<squeal::mesh::volume::VolumeMesh> {
    let path = args.mesh.as_ref().expect("clap group: --wheel or --mesh");
    let mesh = squeal::mesh::volume_io::read(path).map_err(|e| match e {
        Error::Io { path, source } => Error::input(
            path,
            "--mesh",
            format!(
                "cannot read the mesh file ({})",
                squeal::error::io_words(&source)
            ),
        ),
        other => other,
    })?;
    Ok(mesh)
}

fn print_solution(args: &ModesArgs, sol: &ModalSolution) {
    println!(
        "solved: {} modes below {} Hz in {:.2} s ({} shift{}, factorisation {:.2} s, largest Krylov basis {}, {} blocks of {})",
        sol.modes.len(),
        args.fmax_hz,
        sol.solve_seconds,
        sol.shifts.len(),
        if sol.shifts.len() == 1 { "" } else { "s" },
        sol.factor_seconds,
        sol.basis_size,
        sol.blocks,
        sol.block_size
    );
    if let Some(count) = sol.sturm_count {
        println!(
            "Sturm count: {count} eigenvalues below {} Hz, all found",
            args.fmax_hz
        );
    }
}

type Shapes = Vec<(f64, f64, bool, Vec<[f64; 3]>)>;

fn positive(v: Option<f64>, default: f64, name: &str, max: f64) -> Result<f64> {
    match v {
        None => Ok(default),
        Some(x) if x.is_finite() && x > 0.0 && x <= max => Ok(x),
        Some(x) => Err(Error::input(
            "command line",
            name,
            format!("{x} is outside the allowed range (0, {max:e}]"),
        )),
    }
}

fn write_outputs(
    args: &ModesArgs,
    dir: &Path,
    sol: &ModalSolution,
    shapes: &Shapes,
    records: &[ModeRecord],
    nodes_m: &[squeal::mesh::P3],
    write_vtu: impl FnOnce(&Path, &[vtu::PointVectorField]) -> Result<()>,
) -> Result<()> {
    let refs: Vec<_> = records.iter().map(|r| r.mode_ref()).collect();
    squeal::modal::mode::write_modes_json(dir, &refs)?;
    let p = dir.join("modes_detail.json");
    let json = serde_json::to_string_pretty(&records).expect("serialisable");
    std::fs::write(&p, json).map_err(|e| Error::io(&p, e))?;
    let mut csv = String::from(
        "index,frequency_hz,family,nodal_circles,nodal_diameters,residual,residual_floor,pair,rigid\n",
    );
    println!(
        "{:>4} {:>10} {:>16} {:>6} {:>10} {:>5}",
        "#", "f (Hz)", "family", "(m,n)", "residual", "pair"
    );
    for r in records {
        let fam = serde_json::to_value(r.family)
            .expect("family")
            .as_str()
            .unwrap_or("")
            .to_string();
        csv.push_str(&format!(
            "{},{:.6},{},{},{},{:.3e},{:.3e},{},{}\n",
            r.index,
            r.frequency_hz,
            fam,
            r.nodal_circles,
            r.nodal_diameters,
            r.residual,
            r.residual_floor,
            r.is_pair,
            r.rigid
        ));
        println!(
            "{:>4} {:>10.2} {:>16} {:>6} {:>10.2e} {:>5}",
            r.index,
            r.frequency_hz,
            fam,
            format!("({},{})", r.nodal_circles, r.nodal_diameters),
            r.residual,
            if r.is_pair { "yes" } else { "" }
        );
    }
    let p = dir.join("modes.csv");
    std::fs::write(&p, csv).map_err(|e| Error::io(&p, e))?;
    let names: Vec<String> = sol
        .modes
        .iter()
        .enumerate()
        .map(|(i, m)| format!("mode_{:03}_{:.1}Hz", i, m.frequency_hz))
        .collect();
    let fields: Vec<vtu::PointVectorField> = shapes
        .iter()
        .zip(&names)
        .map(|(s, name)| vtu::PointVectorField {
            name: name.clone(),
            values: &s.3,
        })
        .collect();
    write_vtu(dir, &fields)?;
    let mut measured_modes = None;
    if let Some(h) = &args.hammer {
        let fe = super::hammer::FeShapesOnMesh {
            nodes_m,
            members: records
                .iter()
                .map(|r| r.members.iter().map(|&k| shapes[k].3.as_slice()).collect())
                .collect(),
        };
        measured_modes = Some(super::hammer::compare_hammer(
            h,
            &refs,
            Some(&fe),
            args.fmax_hz,
            dir,
        )?);
    }
    // The paper's modal chart, measured modes solid when a hammer test is given.
    squeal::report::modal_chart::write_modal_chart(
        &refs,
        measured_modes.as_deref(),
        Some(&dir.join("modal_chart.png")),
        Some(&dir.join("modal_chart.svg")),
    )?;
    Ok(())
}

/// Writes K.mtx and M.mtx (Matrix Market) of the reduced system into `dir`.
fn export_matrices(asm: &squeal::fem::Assembled, dir: &std::path::Path) -> Result<()> {
    // Written beside the folder and moved into it when both are complete.
    let stage = StagedDir::new(dir)?;
    write_matrix_market(&asm.k, &stage.path().join("K.mtx"))?;
    write_matrix_market(&asm.m, &stage.path().join("M.mtx"))?;
    stage.commit(Commit::Merge)?;
    println!("wrote {}/K.mtx and M.mtx", dir.display());
    Ok(())
}
