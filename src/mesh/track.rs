//! The track: the 54E1 rail section extruded along x with graded spacing (fine in the solution
//! zone, growing geometrically to a coarse size elsewhere), inclined 1:40 towards the track
//! centre, and coarse hexahedral sleeper blocks under it. Rail pads and ballast are springs and
//! dampers added by the explicit engine; here they are recorded as named node sets.

use serde::Serialize;

use super::distribute;
use super::rail::{rail_section, RailSectionSizes};
use super::rail_insert;
pub use super::rail_insert::RailInsertSpec;
use super::section::SectionMesh;
use super::{material, Mesh, P3};
use crate::geometry::rail54e1;

/// Track geometry and mesh settings (SI units unless the name says otherwise).
#[derive(Clone, Debug, Serialize)]
pub struct TrackLayout {
    /// Track (rail) length along x (m); the rail runs from x = 0 to x = length.
    pub length_m: f64,
    /// Lateral position of the rail section origin (crown top of the upright section) (m).
    pub rail_origin_y_m: f64,
    /// Height of the rail section origin (m).
    pub rail_origin_z_m: f64,
    /// Solution zone start (m).
    pub solution_zone_start_m: f64,
    /// Solution zone length (m).
    pub solution_zone_length_m: f64,
    /// Element length along x in the solution zone (m).
    pub zone_element_length_m: f64,
    /// A medium-size stretch of rail over the whole path the wheel rolls (None: the rail grows
    /// from the solution zone to the far size): a coarse rail under a rolling wheel gives a
    /// contact stiffness that varies with the element passing.
    pub running_zone: Option<RailZone>,
    /// Largest element length along x (m).
    pub far_element_length_m: f64,
    /// Growth ratio of element length away from the zone.
    pub growth_ratio: f64,
    /// Section element size on the running surface (mm).
    pub running_surface_element_mm: f64,
    /// Section element size in web and foot (mm).
    pub section_element_mm: f64,
    /// Sleeper spacing (m).
    pub sleeper_spacing_m: f64,
    /// x of the first sleeper centre (m).
    pub first_sleeper_x_m: f64,
    /// Sleeper width along x (m).
    pub sleeper_width_m: f64,
    /// Sleeper height (m).
    pub sleeper_height_m: f64,
    /// Lateral extent of the (half) sleeper: from `sleeper_y_min_m` to `sleeper_y_max_m`.
    pub sleeper_y_min_m: f64,
    /// See `sleeper_y_min_m`.
    pub sleeper_y_max_m: f64,
    /// Element divisions of a sleeper block along x, y, z.
    pub sleeper_divisions: [usize; 3],
    /// Rail pad thickness: gap between rail foot and sleeper top (m).
    pub pad_thickness_m: f64,
    /// Rail pad length along x (m).
    pub pad_length_m: f64,
    /// A finer block tied into the rail's running band (None: none).
    pub rail_insert: Option<RailInsertSpec>,
}

/// A stretch of rail with its own element length along x.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct RailZone {
    /// Start along x (m).
    pub start_m: f64,
    /// Length (m).
    pub length_m: f64,
    /// Element length along x inside the stretch (m).
    pub element_length_m: f64,
}

/// Rotate an upright rail-section point (mm) by the 1:40 inclination (top towards -y, the
/// track centre) and place it (m).
pub fn place_rail_point(layout: &TrackLayout, y_mm: f64, z_mm: f64) -> [f64; 2] {
    let (s, c) = rail54e1::INCLINATION_RAD.sin_cos();
    let y = y_mm * c - z_mm * s;
    let z = y_mm * s + z_mm * c;
    [
        layout.rail_origin_y_m + y * 1e-3,
        layout.rail_origin_z_m + z * 1e-3,
    ]
}

/// Stations along x of the running band (or of the whole rail when there is no band): the
/// zone element length in the solution zone, graded to the far size.
pub fn rail_stations(layout: &TrackLayout) -> Vec<f64> {
    stations_with_zone_size(layout, layout.zone_element_length_m)
}

/// Stations of the rail body under a running band: in the zone, no finer than the body's
/// section size.
pub fn rail_body_stations(layout: &TrackLayout) -> Vec<f64> {
    stations_with_zone_size(
        layout,
        layout
            .zone_element_length_m
            .max(1e-3 * layout.section_element_mm),
    )
}

fn stations_with_zone_size(layout: &TrackLayout, zone_size_m: f64) -> Vec<f64> {
    let z0 = layout.solution_zone_start_m;
    let z1 = z0 + layout.solution_zone_length_m;
    // Cap the far size so every rail pad holds at least two stations.
    let coarse = layout.far_element_length_m.min(0.5 * layout.pad_length_m);
    let running = layout.running_zone.map(|r| {
        (
            r.start_m,
            r.start_m + r.length_m,
            r.element_length_m.max(zone_size_m).min(coarse),
        )
    });
    let size =
        distribute::nested_graded_size((z0, z1, zone_size_m), running, coarse, layout.growth_ratio);
    distribute::by_size_function(layout.length_m, size, 2)
}

fn extrude(section: &SectionMesh, stations: &[f64], layout: &TrackLayout) -> Mesh {
    let ns = stations.len();
    let mut mesh = Mesh::default();
    mesh.nodes.reserve(section.nodes.len() * ns);
    for p in &section.nodes {
        let [y, z] = place_rail_point(layout, p[0], p[1]);
        for &x in stations {
            mesh.nodes.push([x, y, z]);
        }
    }
    let node = |id: usize, k: usize| id * ns + k;
    mesh.elements.reserve(section.quads.len() * (ns - 1));
    for (qi, q) in section.quads.iter().enumerate() {
        for k in 0..ns - 1 {
            mesh.elements.push(super::hex::swept(*q, k, node));
            mesh.material.push(section.quad_part[qi]);
        }
    }
    for (name, ids) in &section.tags {
        mesh.add_node_set(
            &format!("rail_{name}"),
            ids.iter().flat_map(|&id| (0..ns).map(move |k| node(id, k))),
        );
    }
    let first: Vec<usize> = (0..section.nodes.len()).map(|id| node(id, 0)).collect();
    let last: Vec<usize> = (0..section.nodes.len())
        .map(|id| node(id, ns - 1))
        .collect();
    mesh.add_node_set("rail_end_start", first.iter().copied());
    mesh.add_node_set("rail_end_finish", last.iter().copied());
    mesh.add_node_set("rail_ends", first.into_iter().chain(last));
    mesh
}

/// Sleeper centres along x that fit in the track.
pub fn sleeper_positions(layout: &TrackLayout) -> Vec<f64> {
    let mut out = Vec::new();
    let mut x = layout.first_sleeper_x_m;
    while x + 0.5 * layout.sleeper_width_m <= layout.length_m + 1e-12 {
        if x - 0.5 * layout.sleeper_width_m >= -1e-12 {
            out.push(x);
        }
        x += layout.sleeper_spacing_m;
    }
    out
}

/// Build the track mesh: rail + sleepers, with node sets `rail_running_surface`,
/// `rail_foot_bottom`, `rail_ends`, `rail_pad_<k>` / `rail_pads`, `sleeper_top_<k>` /
/// `sleeper_tops`, `sleeper_bottom_<k>` / `sleeper_bottoms`, `sleeper_centre_faces` (the
/// sleepers' cut at the track centre) and surface `rail_top`.
pub fn track_mesh(layout: &TrackLayout) -> Mesh {
    let section = rail_section(RailSectionSizes {
        running_surface_mm: layout.running_surface_element_mm,
        body_mm: layout.section_element_mm,
        band_rows_at_least: if layout.rail_insert.is_some() { 2 } else { 1 },
    });
    let mut mesh = match &section.band {
        None => extrude(&section.body, &rail_stations(layout), layout),
        Some(band) => {
            let mut body = extrude(&section.body, &rail_body_stations(layout), layout);
            let stations = rail_stations(layout);
            let mut band_mesh = extrude(band, &stations, layout);
            // The insert's hole is cut while the band's elements are in the swept order.
            let insert = layout.rail_insert.as_ref().map(|ins| {
                let map = section.band_map.as_ref().expect("band map with the band");
                let place = |p: [f64; 2], x: f64| {
                    let [y, z] = place_rail_point(layout, p[0], p[1]);
                    [x, y, z]
                };
                rail_insert::cut(&mut band_mesh, ins, map, &stations, place)
            });
            let offset = body.nodes.len();
            body.append(band_mesh);
            body.orient_elements();
            let slaves = body
                .node_sets
                .remove("rail_band_interface")
                .unwrap_or_default();
            let iface = body
                .node_sets
                .remove("rail_band_interface_body")
                .unwrap_or_default();
            let mut member = vec![false; body.nodes.len()];
            for &i in &iface {
                member[i] = true;
            }
            let masters: Vec<[usize; 4]> = body
                .boundary_faces()
                .into_iter()
                .filter(|(f, e)| {
                    body.material[*e] == material::RAIL
                        && f.iter().all(|&i| i < offset && member[i])
                })
                .map(|(f, _)| f)
                .collect();
            body.ties.push(super::tie::build(
                "rail_running_band",
                &body.nodes,
                &slaves,
                &masters,
            ));
            if let Some((walls, block)) = insert {
                let walls: Vec<[usize; 4]> = walls.iter().map(|f| f.map(|n| n + offset)).collect();
                super::insert::tie_insert(&mut body, &walls, block, "rail_insert");
            }
            body
        }
    };
    mesh.orient_elements();
    // Lowest point of the inclined rail foot: the sleeper tops sit one pad thickness below it.
    let foot = mesh.node_set("rail_foot_bottom").unwrap_or(&[]).to_vec();
    let foot_min_z = foot
        .iter()
        .map(|&i| mesh.nodes[i][2])
        .fold(f64::INFINITY, f64::min);
    let sleeper_top_z = foot_min_z - layout.pad_thickness_m;
    let mut pads_all = Vec::new();
    for (k, &xc) in sleeper_positions(layout).iter().enumerate() {
        let pad: Vec<usize> = foot
            .iter()
            .copied()
            .filter(|&i| (mesh.nodes[i][0] - xc).abs() <= 0.5 * layout.pad_length_m + 1e-12)
            .collect();
        pads_all.extend(pad.iter().copied());
        mesh.add_node_set(&format!("rail_pad_{k}"), pad);
        let block = sleeper_block(layout, xc, sleeper_top_z);
        let offset = mesh.nodes.len();
        let [nx, ny, nz] = layout.sleeper_divisions;
        let id = |i: usize, j: usize, l: usize| offset + (i * (ny + 1) + j) * (nz + 1) + l;
        let tops: Vec<usize> = (0..=nx)
            .flat_map(|i| (0..=ny).map(move |j| id(i, j, nz)))
            .collect();
        let bottoms: Vec<usize> = (0..=nx)
            .flat_map(|i| (0..=ny).map(move |j| id(i, j, 0)))
            .collect();
        // The half sleeper's cut at the track centre (y = sleeper_y_min_m): the half-track
        // model's plane of symmetry.
        let centre_face: Vec<usize> = (0..=nx)
            .flat_map(|i| (0..=nz).map(move |l| id(i, 0, l)))
            .collect();
        mesh.append(block);
        mesh.add_node_set("sleeper_centre_faces", centre_face);
        mesh.add_node_set(&format!("sleeper_top_{k}"), tops.iter().copied());
        mesh.add_node_set(&format!("sleeper_bottom_{k}"), bottoms.iter().copied());
        mesh.add_node_set("sleeper_tops", tops);
        mesh.add_node_set("sleeper_bottoms", bottoms);
    }
    mesh.add_node_set("rail_pads", pads_all);
    mesh.surface_from_node_set("rail_top", "rail_running_surface", None);
    mesh
}

fn sleeper_block(layout: &TrackLayout, x_centre: f64, top_z: f64) -> Mesh {
    let [nx, ny, nz] = layout.sleeper_divisions;
    let xs = distribute::uniform(
        x_centre - 0.5 * layout.sleeper_width_m,
        x_centre + 0.5 * layout.sleeper_width_m,
        nx,
    );
    let ys = distribute::uniform(layout.sleeper_y_min_m, layout.sleeper_y_max_m, ny);
    let zs = distribute::uniform(top_z - layout.sleeper_height_m, top_z, nz);
    let mut mesh = Mesh::default();
    for &x in &xs {
        for &y in &ys {
            for &z in &zs {
                mesh.nodes.push([x, y, z] as P3);
            }
        }
    }
    let id = |i: usize, j: usize, l: usize| (i * (ny + 1) + j) * (nz + 1) + l;
    for i in 0..nx {
        for j in 0..ny {
            for l in 0..nz {
                mesh.elements.push(super::hex::structured(i, j, l, id));
                mesh.material.push(material::SLEEPER);
            }
        }
    }
    mesh
}
