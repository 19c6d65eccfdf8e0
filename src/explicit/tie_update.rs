//! Tied interfaces in the time step, in parallel. A tie slave `s` sits on its master face with
//! bilinear weights `w_k` (`mesh::tie`): its forces pass to the masters, `f_m += w_k f_s`, and
//! it follows them, `u_s = sum_k w_k u_m` (and `v_s` alike): the rows of `Tᵀ f` and `T q`
//! for the constraint `u = T q`.
//!
//! The force pass is a scatter (neighbouring slaves share masters), so it runs as a gather:
//! each master sums its slaves' shares in the order of the tie list, which adds the same terms
//! onto the same value in the same order as the serial loop over the ties, so the result is
//! the serial one bit for bit on any number of threads. The follow step writes each slave once
//! and reads only masters, which the solver guarantees are never slaves (no chained ties).

// Index loops mirror the tensor notation of the equations (the project's style for kernels).
#![allow(clippy::needless_range_loop)]

use rayon::prelude::*;

use super::colour::SharedMut;
use super::state::OutputFields;
use crate::mesh::tie::TiePair;
use crate::mesh::P3;

/// Masters (or ties) per parallel task: large enough that a task outweighs its scheduling.
const TIE_CHUNK: usize = 2048;

/// Each master's share of the tie slaves: the force pass as a gather.
#[derive(Clone, Debug, Default)]
pub(super) struct TieGather {
    /// The masters, ascending.
    masters: Vec<usize>,
    /// `entries[start[i]..start[i + 1]]` are master `masters[i]`'s `(slave, weight)`, in the
    /// order of the tie list.
    start: Vec<usize>,
    entries: Vec<(usize, f64)>,
}

impl TieGather {
    /// The gather of `ties` over `node_count` nodes.
    pub(super) fn new(ties: &[TiePair], node_count: usize) -> Self {
        let mut count = vec![0usize; node_count];
        for p in ties {
            for &m in &p.master {
                count[m] += 1;
            }
        }
        let masters: Vec<usize> = (0..node_count).filter(|&m| count[m] > 0).collect();
        let mut start = Vec::with_capacity(masters.len() + 1);
        let mut slot = vec![0usize; node_count];
        let mut total = 0;
        for &m in &masters {
            start.push(total);
            slot[m] = total;
            total += count[m];
        }
        start.push(total);
        // A stable placement: each master's entries in tie order, then face-corner order.
        let mut entries = vec![(0usize, 0.0); total];
        for p in ties {
            for (k, &m) in p.master.iter().enumerate() {
                entries[slot[m]] = (p.slave, p.weights[k]);
                slot[m] += 1;
            }
        }
        TieGather {
            masters,
            start,
            entries,
        }
    }

    /// `f_m += w f_s` for one force array, every master in parallel.
    pub(super) fn pass(&self, force: &mut [P3]) {
        let f_ptr = SharedMut(force.as_mut_ptr());
        self.masters
            .par_chunks(TIE_CHUNK)
            .enumerate()
            .for_each(|(c, masters)| {
                for (j, &m) in masters.iter().enumerate() {
                    let i = c * TIE_CHUNK + j;
                    let entries = &self.entries[self.start[i]..self.start[i + 1]];
                    // SAFETY: each master is written by one task; the slaves read are never
                    // masters (Solver::new refuses chained ties), so nothing read is written.
                    unsafe {
                        let mut f = *f_ptr.at(m);
                        for &(s, w) in entries {
                            let fs = *f_ptr.at(s);
                            for d in 0..3 {
                                f[d] += w * fs[d];
                            }
                        }
                        *f_ptr.at(m) = f;
                    }
                }
            });
    }
}

/// Tie slaves follow their masters: `u_s`, `v_s` interpolated; with `output`, the output
/// velocity and acceleration interpolated from the masters' and the displacement before the
/// update (the state of t_n, as the node loop writes it). Every tie in parallel.
pub(super) fn follow_masters(
    ties: &[TiePair],
    u: &mut [P3],
    v: &mut [P3],
    output: Option<&mut OutputFields>,
) {
    let (u_ptr, v_ptr) = (SharedMut(u.as_mut_ptr()), SharedMut(v.as_mut_ptr()));
    let out_ptrs = output.map(|o| {
        (
            SharedMut(o.displacement.as_mut_ptr()),
            SharedMut(o.velocity.as_mut_ptr()),
            SharedMut(o.acceleration.as_mut_ptr()),
        )
    });
    ties.par_chunks(TIE_CHUNK).for_each(|chunk| {
        for p in chunk {
            // SAFETY: each slave belongs to one tie (Solver::new refuses a node tied twice)
            // and masters are never slaves, so every index written is written by one task and
            // never read by another.
            unsafe {
                let (us, vs) = (on_face(p, u_ptr), on_face(p, v_ptr));
                if let Some((od, ov, oa)) = out_ptrs {
                    let (vo, ao) = (on_face(p, ov), on_face(p, oa));
                    *od.at(p.slave) = *u_ptr.at(p.slave);
                    *ov.at(p.slave) = vo;
                    *oa.at(p.slave) = ao;
                }
                *u_ptr.at(p.slave) = us;
                *v_ptr.at(p.slave) = vs;
            }
        }
    });
}

/// `sum_k w_k field[master_k]`: a nodal field interpolated at the slave's place on its face.
///
/// # Safety
/// `field` points at a node array holding every master of `p`, which no other task writes.
#[inline(always)]
unsafe fn on_face(p: &TiePair, field: SharedMut<P3>) -> P3 {
    let mut x = [0.0; 3];
    for (k, &m) in p.master.iter().enumerate() {
        let xm = *field.at(m);
        for i in 0..3 {
            x[i] += p.weights[k] * xm[i];
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::XorShift64;

    /// Random ties over 2000 nodes (slaves 0..600, masters drawn from 600..2000, so neighbouring
    /// slaves share masters) against the serial loops, bit for bit, on 1 and 2 threads.
    #[test]
    fn parallel_ties_match_the_serial_loops_bit_for_bit() {
        let n = 2000;
        let mut rng = XorShift64::seeded(7);
        let ties: Vec<TiePair> = (0..600)
            .map(|s| {
                let base = 600 + rng.below(1390);
                let w = [0.1 + 0.2 * rng.centred_uniform(), 0.3, 0.2, 0.0];
                TiePair {
                    slave: s,
                    master: [base, base + 1, base + 5, base + 9],
                    weights: [w[0], w[1], w[2], 1.0 - w[0] - w[1] - w[2]],
                    gap_m: 0.0,
                }
            })
            .collect();
        let field = |rng: &mut XorShift64| -> Vec<P3> {
            (0..n)
                .map(|_| [0, 1, 2].map(|_| rng.centred_uniform()))
                .collect()
        };
        let (f_int0, f_aux0, u0, v0) = (
            field(&mut rng),
            field(&mut rng),
            field(&mut rng),
            field(&mut rng),
        );
        // The serial loops as the time step had them.
        let (mut fi_ref, mut fa_ref) = (f_int0.clone(), f_aux0.clone());
        for p in &ties {
            let (fi, fa) = (fi_ref[p.slave], fa_ref[p.slave]);
            for (k, &m) in p.master.iter().enumerate() {
                for i in 0..3 {
                    fi_ref[m][i] += p.weights[k] * fi[i];
                    fa_ref[m][i] += p.weights[k] * fa[i];
                }
            }
        }
        let (mut u_ref, mut v_ref) = (u0.clone(), v0.clone());
        for p in &ties {
            let (mut us, mut vs) = ([0.0; 3], [0.0; 3]);
            for (k, &m) in p.master.iter().enumerate() {
                for i in 0..3 {
                    us[i] += p.weights[k] * u_ref[m][i];
                    vs[i] += p.weights[k] * v_ref[m][i];
                }
            }
            u_ref[p.slave] = us;
            v_ref[p.slave] = vs;
        }
        let gather = TieGather::new(&ties, n);
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let (mut fi, mut fa, mut u, mut v) =
                (f_int0.clone(), f_aux0.clone(), u0.clone(), v0.clone());
            let mut out = OutputFields {
                displacement: vec![[0.0; 3]; n],
                velocity: field(&mut rng),
                acceleration: field(&mut rng),
                rigid_reaction_force_n: Vec::new(),
            };
            pool.install(|| {
                gather.pass(&mut fi);
                gather.pass(&mut fa);
                follow_masters(&ties, &mut u, &mut v, Some(&mut out));
            });
            assert_eq!(fi, fi_ref, "{threads} threads");
            assert_eq!(fa, fa_ref, "{threads} threads");
            assert_eq!(u, u_ref, "{threads} threads");
            assert_eq!(v, v_ref, "{threads} threads");
            // Output: the slave's displacement of t_n and the masters' interpolated fields.
            let p = &ties[17];
            assert_eq!(out.displacement[p.slave], u0[p.slave]);
            let mut vo = [0.0; 3];
            for (k, &m) in p.master.iter().enumerate() {
                for i in 0..3 {
                    vo[i] += p.weights[k] * out.velocity[m][i];
                }
            }
            assert_eq!(out.velocity[p.slave], vo);
        }
    }
}
