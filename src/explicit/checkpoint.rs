//! The checkpoint file: the solver's whole state, so that a run goes on from it exactly.
//!
//! Layout (little-endian 8-byte words): a header word naming the layout, the run's stamp
//! ([`RunStamp`]: a flag, the fingerprint of its inputs and the numerics version), the model's
//! fingerprint ([`model_fingerprint`]), the node, rigid-body and auxiliary counts, the step, the
//! time and the time step, displacements and velocities, the work totals, the rigid bodies,
//! the auxiliary state (contact, friction, drives), an optional multi-rate tail, and a
//! checksum (FNV-1a of every byte before it). A resume refuses a file whose checksum, model or
//! stamp differs, so that a damaged file or another run's is never carried on.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use super::solver::{RigidState, Solver, WorkTotals};
use crate::mesh::P3;
use crate::{Error, Result};

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |e| Error::io(path, e)
}

/// What a checkpoint's run computed with: a fingerprint of its inputs and the numerics version
/// of the binary (the caller's, e.g. `rolling::identity`). A resume with another stamp would
/// carry on a run with other values than it started with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunStamp {
    /// Fingerprint of the inputs (case and model).
    pub fingerprint: u64,
    /// Numerics version of the binary that wrote the checkpoint.
    pub numerics_version: u64,
}

/// Checkpoint layouts: version 3 holds the run's stamp after the header word and ends with a
/// checksum; version 2 (checksum, no stamp) and version 1 (neither) are still read.
const MAGIC: &[u8; 8] = b"SQLCKPT3";
const MAGIC_V2: &[u8; 8] = b"SQLCKPT2";
const MAGIC_V1: &[u8; 8] = b"SQLCKPT1";
/// Marks the checksum that ends a version-2 checkpoint: FNV-1a (64 bit) of every byte before
/// the mark. A flipped byte anywhere changes it (each byte passes through the multiply of
/// every later one), so a damaged file is refused instead of resumed into a blow-up.
const CHECKSUM_MARK: &[u8; 8] = b"SQLCSUM1";
/// Marks the optional multi-rate tail of a checkpoint (after the auxiliary state).
const MULTI_RATE_TAIL: &[u8; 8] = b"SQLMRAC1";

/// FNV-1a (64 bit) of a byte string.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    h
}

/// Fingerprint of a model: FNV-1a over node and element counts, reference coordinates and
/// masses. A checkpoint of another model is refused.
pub fn model_fingerprint(solver: &Solver) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    let mut eat = |x: u64| {
        for b in x.to_le_bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x100000001b3);
        }
    };
    eat(solver.u.len() as u64);
    eat(solver.model.elements.len() as u64);
    for p in &solver.model.mesh.nodes {
        for c in p {
            eat(c.to_bits());
        }
    }
    for m in &solver.model.nodal_mass_kg {
        eat(m.to_bits());
    }
    h
}

fn put(buf: &mut Vec<u8>, x: f64) {
    buf.extend_from_slice(&x.to_le_bytes());
}

/// Refuses a checkpoint whose stamp differs from the run's. A checkpoint without one (an
/// older layout, or written by a run that gave none) is not checked.
pub(super) fn check_stamp(
    stored: Option<RunStamp>,
    run: Option<RunStamp>,
    path: &Path,
) -> Result<()> {
    let (Some(stored), Some(run)) = (stored, run) else {
        return Ok(());
    };
    let why = if stored.numerics_version != run.numerics_version {
        format!(
            "it was written by a binary of numerics version {}, this one is version {}: resume              the run with the binary that started it",
            stored.numerics_version, run.numerics_version
        )
    } else if stored.fingerprint != run.fingerprint {
        "it was written by a run of another case or model (its fingerprint differs from this          case's): put the case and model back as they were, or start a new run in another          folder"
            .to_string()
    } else {
        return Ok(());
    };
    Err(Error::input(
        path.display().to_string(),
        "checkpoint",
        format!("the run cannot go on from this checkpoint: {why}"),
    ))
}

/// Writes the state (atomically: temporary file, then rename), without a stamp.
pub fn write_checkpoint(solver: &Solver, aux_state: &[f64], path: &Path) -> Result<()> {
    write_checkpoint_stamped(solver, aux_state, None, path)
}

/// Writes the state with the run's `stamp` (atomically: temporary file, then rename).
pub fn write_checkpoint_stamped(
    solver: &Solver,
    aux_state: &[f64],
    stamp: Option<RunStamp>,
    path: &Path,
) -> Result<()> {
    let mut buf = Vec::with_capacity(16 * 3 * solver.u.len() * 2 + 1024);
    buf.extend_from_slice(MAGIC);
    // The stamp: a flag word (1 when present), the fingerprint and the numerics version.
    let (flag, stamp) = match stamp {
        Some(s) => (1u64, s),
        None => (
            0u64,
            RunStamp {
                fingerprint: 0,
                numerics_version: 0,
            },
        ),
    };
    for w in [flag, stamp.fingerprint, stamp.numerics_version] {
        buf.extend_from_slice(&w.to_le_bytes());
    }
    buf.extend_from_slice(&model_fingerprint(solver).to_le_bytes());
    buf.extend_from_slice(&(solver.u.len() as u64).to_le_bytes());
    buf.extend_from_slice(&(solver.rigid.len() as u64).to_le_bytes());
    buf.extend_from_slice(&(aux_state.len() as u64).to_le_bytes());
    buf.extend_from_slice(&solver.step.to_le_bytes());
    put(&mut buf, solver.time_s);
    put(&mut buf, solver.dt_s);
    for arr in [&solver.u, &solver.v] {
        for p in arr.iter() {
            for c in p {
                put(&mut buf, *c);
            }
        }
    }
    for x in solver.work.to_array() {
        put(&mut buf, x);
    }
    for r in &solver.rigid {
        put(&mut buf, r.mass_kg);
        for v in [
            r.centre0_m,
            r.centre_m,
            r.velocity_m_per_s,
            r.angular_momentum,
        ] {
            for c in v {
                put(&mut buf, c);
            }
        }
        for m in [r.rotation, r.inertia0, r.inertia0_inv] {
            for row in m {
                for c in row {
                    put(&mut buf, c);
                }
            }
        }
    }
    for x in aux_state {
        put(&mut buf, *x);
    }
    if let Some(mr) = &solver.multi_rate {
        // Optional tail: each node's acceleration at its last update, which places a coarse
        // node's output velocity between its updates (a checkpoint without it resumes the same
        // motion, with those output velocities off until each node's next update).
        buf.extend_from_slice(MULTI_RATE_TAIL);
        for a in &mr.last_acceleration {
            for c in a {
                put(&mut buf, *c);
            }
        }
    }
    let checksum = fnv1a(&buf);
    buf.extend_from_slice(CHECKSUM_MARK);
    buf.extend_from_slice(&checksum.to_le_bytes());
    let tmp = path.with_extension("bin.tmp");
    std::fs::write(&tmp, &buf).map_err(io(&tmp))?;
    std::fs::rename(&tmp, path).map_err(io(path))
}

/// Reads a checkpoint into the solver; returns the auxiliary state.
pub fn read_checkpoint(solver: &mut Solver, path: &Path) -> Result<Vec<f64>> {
    read_checkpoint_stamped(solver, path).map(|(aux, _)| aux)
}

/// Reads a checkpoint into the solver; returns the auxiliary state and the run's stamp (None
/// when the checkpoint holds none).
pub fn read_checkpoint_stamped(
    solver: &mut Solver,
    path: &Path,
) -> Result<(Vec<f64>, Option<RunStamp>)> {
    let mut bytes = Vec::new();
    File::open(path)
        .map_err(io(path))?
        .read_to_end(&mut bytes)
        .map_err(io(path))?;
    let bad = |msg: &str| Error::input(path.display().to_string(), "checkpoint", msg.to_string());
    let layout: [u8; 8] = bytes
        .get(..8)
        .and_then(|s| s.try_into().ok())
        .unwrap_or_default();
    if bytes.len() < 64 || (&layout != MAGIC && &layout != MAGIC_V2 && &layout != MAGIC_V1) {
        return Err(bad("not a squeal checkpoint (bad header)"));
    }
    let stamped = &layout == MAGIC;
    if &layout != MAGIC_V1 {
        let body_len = bytes.len().saturating_sub(16);
        let trailer = &bytes[body_len..];
        let stored = u64::from_le_bytes(trailer[8..].try_into().expect("8 bytes"));
        if &trailer[..8] != CHECKSUM_MARK || stored != fnv1a(&bytes[..body_len]) {
            return Err(bad(
                "the checkpoint is damaged (its checksum does not match its contents): the run \
                 cannot go on from it; start it again without --resume (its outputs up to the \
                 checkpoint are kept as they are)",
            ));
        }
        bytes.truncate(body_len);
    }
    let mut pos = 8;
    let mut word = |bytes: &[u8]| -> Result<[u8; 8]> {
        let w: [u8; 8] = bytes
            .get(pos..pos + 8)
            .and_then(|s| s.try_into().ok())
            .ok_or_else(|| bad("file is truncated"))?;
        pos += 8;
        Ok(w)
    };
    let stamp = if stamped {
        let flag = u64::from_le_bytes(word(&bytes)?);
        let fingerprint = u64::from_le_bytes(word(&bytes)?);
        let numerics_version = u64::from_le_bytes(word(&bytes)?);
        (flag == 1).then_some(RunStamp {
            fingerprint,
            numerics_version,
        })
    } else {
        None
    };
    let fingerprint = u64::from_le_bytes(word(&bytes)?);
    if fingerprint != model_fingerprint(solver) {
        return Err(bad(
            "checkpoint was written for another model (mesh, masses or node count differ)",
        ));
    }
    let n = u64::from_le_bytes(word(&bytes)?) as usize;
    let n_rigid = u64::from_le_bytes(word(&bytes)?) as usize;
    let n_aux = u64::from_le_bytes(word(&bytes)?) as usize;
    if n != solver.u.len() || n_rigid != solver.rigid.len() {
        return Err(bad(
            "checkpoint node or rigid-body count differs from the model",
        ));
    }
    let step = u64::from_le_bytes(word(&bytes)?);
    let mut f = |bytes: &[u8]| -> Result<f64> { Ok(f64::from_le_bytes(word(bytes)?)) };
    let time_s = f(&bytes)?;
    let dt_s = f(&bytes)?;
    let mut read_vecs = |bytes: &[u8]| -> Result<Vec<P3>> {
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            out.push([f(bytes)?, f(bytes)?, f(bytes)?]);
        }
        Ok(out)
    };
    let u = read_vecs(&bytes)?;
    let v = read_vecs(&bytes)?;
    let mut f = |bytes: &[u8]| -> Result<f64> { Ok(f64::from_le_bytes(word(bytes)?)) };
    let mut terms = [0.0; 10];
    for t in terms.iter_mut() {
        *t = f(&bytes)?;
    }
    let work = WorkTotals::from_array(terms);
    let mut rigid = Vec::with_capacity(n_rigid);
    for _ in 0..n_rigid {
        let mass_kg = f(&bytes)?;
        let mut v3 = || -> Result<P3> { Ok([f(&bytes)?, f(&bytes)?, f(&bytes)?]) };
        let (centre0_m, centre_m, velocity_m_per_s, angular_momentum) =
            (v3()?, v3()?, v3()?, v3()?);
        let mut m3 = || -> Result<[[f64; 3]; 3]> {
            let mut m = [[0.0; 3]; 3];
            for row in m.iter_mut() {
                for c in row.iter_mut() {
                    *c = f(&bytes)?;
                }
            }
            Ok(m)
        };
        let (rotation, inertia0, inertia0_inv) = (m3()?, m3()?, m3()?);
        rigid.push(RigidState {
            mass_kg,
            centre0_m,
            centre_m,
            velocity_m_per_s,
            rotation,
            angular_momentum,
            inertia0,
            inertia0_inv,
        });
    }
    let mut aux = Vec::with_capacity(n_aux);
    for _ in 0..n_aux {
        aux.push(f(&bytes)?);
    }
    let tail_at = pos;
    let last_acceleration = match bytes.get(tail_at..tail_at + 8) {
        Some(tag) if tag == MULTI_RATE_TAIL => {
            let values = bytes
                .get(tail_at + 8..tail_at + 8 + 24 * n)
                .ok_or_else(|| bad("file is truncated (multi-rate tail)"))?;
            let value = |i: usize| {
                f64::from_le_bytes(values[8 * i..8 * i + 8].try_into().expect("8 bytes"))
            };
            Some(
                (0..n)
                    .map(|i| [0, 1, 2].map(|d| value(3 * i + d)))
                    .collect(),
            )
        }
        _ => None,
    };
    solver.restore(time_s, step, dt_s, u, v, work, rigid);
    if let (Some(acc), Some(mr)) = (last_acceleration, solver.multi_rate.as_mut()) {
        mr.last_acceleration = acc;
    }
    Ok((aux, stamp))
}
