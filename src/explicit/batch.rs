//! The fast path of the one-point element: four elements at a time, one per SIMD lane
//! (structure of arrays), for the common case of elastic elements with stiffness-type
//! hourglass control and no element damping. It computes exactly what
//! [`super::element::one_point_forces`] computes (the slow, trusted reference it is tested
//! against on random distorted elements) and is compiled twice: with AVX2 + FMA, chosen at run
//! time when the processor has them, and for the baseline target.

// Index loops mirror the tensor notation of the equations (the project's style for kernels);
// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

use super::element::{OnePointElement, HOURGLASS_BASE};
use crate::mesh::P3;

/// Elements per batch (SIMD lanes of f64 in AVX2).
pub const LANES: usize = 4; // the lane-wise operations of `V` are written out for 4

/// Four lanes of f64.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub struct V(pub [f64; LANES]);

impl V {
    #[inline(always)]
    fn splat(x: f64) -> V {
        V([x; LANES])
    }
    #[inline(always)]
    fn add(self, o: V) -> V {
        V([
            self.0[0] + o.0[0],
            self.0[1] + o.0[1],
            self.0[2] + o.0[2],
            self.0[3] + o.0[3],
        ])
    }
    #[inline(always)]
    fn sub(self, o: V) -> V {
        V([
            self.0[0] - o.0[0],
            self.0[1] - o.0[1],
            self.0[2] - o.0[2],
            self.0[3] - o.0[3],
        ])
    }
    #[inline(always)]
    fn mul(self, o: V) -> V {
        V([
            self.0[0] * o.0[0],
            self.0[1] * o.0[1],
            self.0[2] * o.0[2],
            self.0[3] * o.0[3],
        ])
    }
    /// `self * b + c`, fused when `FMA`.
    #[inline(always)]
    fn madd<const FMA: bool>(self, b: V, c: V) -> V {
        if FMA {
            V([
                self.0[0].mul_add(b.0[0], c.0[0]),
                self.0[1].mul_add(b.0[1], c.0[1]),
                self.0[2].mul_add(b.0[2], c.0[2]),
                self.0[3].mul_add(b.0[3], c.0[3]),
            ])
        } else {
            V([
                self.0[0] * b.0[0] + c.0[0],
                self.0[1] * b.0[1] + c.0[1],
                self.0[2] * b.0[2] + c.0[2],
                self.0[3] * b.0[3] + c.0[3],
            ])
        }
    }
    #[inline(always)]
    fn sqrt(self) -> V {
        V([
            self.0[0].sqrt(),
            self.0[1].sqrt(),
            self.0[2].sqrt(),
            self.0[3].sqrt(),
        ])
    }
    #[inline(always)]
    fn recip(self) -> V {
        V([
            1.0 / self.0[0],
            1.0 / self.0[1],
            1.0 / self.0[2],
            1.0 / self.0[3],
        ])
    }
}

/// Four elements' data, lane l = element `4 k + l` (padding lanes repeat a real element's nodes
/// with zero stiffness, so they add exact zeros to nodes their own block owns).
#[derive(Clone, Debug)]
#[repr(C, align(32))]
pub struct ElementBatch {
    /// Mean gradients `b_a` per direction and node.
    pub grad: [[V; 8]; 3],
    /// `sum_b h_alpha,b X_b`.
    pub hourglass_ref: [[V; 3]; 4],
    /// Physical form: reference axes (columns of J at the centre).
    pub axes_ref: [[V; 3]; 3],
    /// Physical form: stiffness per mode and axis; isotropic form: the same value on all axes
    /// of mode 0's slot 0 is not used (see `isotropic_coef`).
    pub axis_coef: [[V; 3]; 4],
    /// Isotropic (Flanagan-Belytschko) coefficient.
    pub isotropic_coef: V,
    /// `lambda V0`.
    pub lambda_vol: V,
    /// `2 mu V0`.
    pub two_mu_vol: V,
    /// Nodes per lane.
    pub nodes: [[u32; LANES]; 8],
    /// Number of real elements in the batch.
    pub count: u32,
}

impl ElementBatch {
    /// Packs up to four elements.
    pub fn pack(elements: &[OnePointElement]) -> ElementBatch {
        assert!(!elements.is_empty() && elements.len() <= LANES);
        let mut b = ElementBatch {
            grad: [[V::default(); 8]; 3],
            hourglass_ref: [[V::default(); 3]; 4],
            axes_ref: [[V::default(); 3]; 3],
            axis_coef: [[V::default(); 3]; 4],
            isotropic_coef: V::default(),
            lambda_vol: V::default(),
            two_mu_vol: V::default(),
            nodes: [[0; LANES]; 8],
            count: elements.len() as u32,
        };
        for l in 0..LANES {
            let (el, real) = match elements.get(l) {
                Some(e) => (e, true),
                None => (&elements[0], false),
            };
            let s = if real { 1.0 } else { 0.0 };
            for a in 0..8 {
                b.nodes[a][l] = el.nodes[a];
                for j in 0..3 {
                    b.grad[j][a].0[l] = el.grad[j][a];
                }
            }
            for alpha in 0..4 {
                for j in 0..3 {
                    b.hourglass_ref[alpha][j].0[l] = el.hourglass_ref[alpha][j];
                    b.axis_coef[alpha][j].0[l] = s * el.hourglass_axis_coef[alpha][j];
                }
            }
            for r in 0..3 {
                for j in 0..3 {
                    // Padding lanes get unit axes so the normalisation stays finite.
                    b.axes_ref[r][j].0[l] = el.axes_ref[r][j];
                }
            }
            b.isotropic_coef.0[l] = s * el.hourglass_coef;
            b.lambda_vol.0[l] = s * el.lambda_vol;
            b.two_mu_vol.0[l] = s * el.two_mu_vol;
        }
        b
    }
}

/// Internal forces of a batch, `force[i][a]` per lane (the caller scatters them).
#[inline(always)]
fn batch_forces<const FMA: bool, const PHYSICAL: bool>(
    b: &ElementBatch,
    u: &[P3],
    force: &mut [[V; 8]; 3],
) {
    let mut ue = [[V::default(); 8]; 3];
    for a in 0..8 {
        for l in 0..LANES {
            // SAFETY: node ids were checked against the node count when the batch was packed
            // (they come from a validated mesh) and u has one entry per node.
            let d = unsafe { *u.get_unchecked(b.nodes[a][l] as usize) };
            ue[0][a].0[l] = d[0];
            ue[1][a].0[l] = d[1];
            ue[2][a].0[l] = d[2];
        }
    }
    // H_ij = sum_a u_ai b_aj
    let mut h = [[V::default(); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let mut acc = ue[i][0].mul(b.grad[j][0]);
            for a in 1..8 {
                acc = ue[i][a].madd::<FMA>(b.grad[j][a], acc);
            }
            h[i][j] = acc;
        }
    }
    // E = (H + H^T + H^T H) / 2
    let half = V::splat(0.5);
    let mut e = [[V::default(); 3]; 3];
    for i in 0..3 {
        for j in i..3 {
            let mut acc = h[i][j].add(h[j][i]);
            for k in 0..3 {
                acc = h[k][i].madd::<FMA>(h[k][j], acc);
            }
            e[i][j] = acc.mul(half);
            e[j][i] = e[i][j];
        }
    }
    let tr = e[0][0].add(e[1][1]).add(e[2][2]);
    let ltr = b.lambda_vol.mul(tr);
    let mut s = [[V::default(); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            s[i][j] = b.two_mu_vol.mul(e[i][j]);
        }
        s[i][i] = s[i][i].add(ltr);
    }
    // P = (I + H) S
    let mut p = [[V::default(); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let mut acc = s[i][j];
            for k in 0..3 {
                acc = h[i][k].madd::<FMA>(s[k][j], acc);
            }
            p[i][j] = acc;
        }
    }
    // Hourglass, rearranged so that g_alpha,a = h_alpha,a - hX_alpha . b_a is never formed:
    //   q_alpha = sum_a h_alpha,a u_a - H hX_alpha,
    //   f_a += sum_alpha g_alpha,a qt_alpha = sum_alpha h_alpha,a qt_alpha - Q b_a,
    //   with Q = sum_alpha qt_alpha (x) hX_alpha, folded into the stress term as (P - Q) b_a.
    let mut qts = [[V::default(); 3]; 4];
    let mut axes = [[V::default(); 3]; 3];
    if PHYSICAL {
        // Current axes t_r = F t_r0 = t_r0 + H t_r0, normalised.
        for r in 0..3 {
            let t0 = b.axes_ref[r];
            for i in 0..3 {
                let mut acc = t0[i];
                for j in 0..3 {
                    acc = h[i][j].madd::<FMA>(t0[j], acc);
                }
                axes[r][i] = acc;
            }
            let n2 = axes[r][0].mul(axes[r][0]);
            let n2 = axes[r][1].madd::<FMA>(axes[r][1], n2);
            let n2 = axes[r][2].madd::<FMA>(axes[r][2], n2);
            let inv = n2.sqrt().recip();
            for i in 0..3 {
                axes[r][i] = axes[r][i].mul(inv);
            }
        }
    }
    for alpha in 0..4 {
        let hx = b.hourglass_ref[alpha];
        let base = &HOURGLASS_BASE[alpha];
        let mut q = [V::default(); 3];
        for i in 0..3 {
            let mut acc = ue[i][0];
            for a in 1..8 {
                acc = if base[a] > 0.0 {
                    acc.add(ue[i][a])
                } else {
                    acc.sub(ue[i][a])
                };
            }
            if base[0] < 0.0 {
                acc = acc.sub(ue[i][0]).sub(ue[i][0]);
            }
            let mut hh = h[i][0].mul(hx[0]);
            hh = h[i][1].madd::<FMA>(hx[1], hh);
            hh = h[i][2].madd::<FMA>(hx[2], hh);
            q[i] = acc.sub(hh);
        }
        qts[alpha] = if PHYSICAL {
            let mut qt = [V::default(); 3];
            for r in 0..3 {
                let t = axes[r];
                let mut pr = q[0].mul(t[0]);
                pr = q[1].madd::<FMA>(t[1], pr);
                pr = q[2].madd::<FMA>(t[2], pr);
                let c = b.axis_coef[alpha][r].mul(pr);
                for i in 0..3 {
                    qt[i] = c.madd::<FMA>(t[i], qt[i]);
                }
            }
            qt
        } else {
            [0, 1, 2].map(|i| q[i].mul(b.isotropic_coef))
        };
    }
    // M = P - Q
    let mut m = p;
    for i in 0..3 {
        for j in 0..3 {
            let mut qsum = qts[0][i].mul(b.hourglass_ref[0][j]);
            for alpha in 1..4 {
                qsum = qts[alpha][i].madd::<FMA>(b.hourglass_ref[alpha][j], qsum);
            }
            m[i][j] = m[i][j].sub(qsum);
        }
    }
    for i in 0..3 {
        for a in 0..8 {
            let mut acc = m[i][0].mul(b.grad[0][a]);
            acc = m[i][1].madd::<FMA>(b.grad[1][a], acc);
            acc = m[i][2].madd::<FMA>(b.grad[2][a], acc);
            for alpha in 0..4 {
                acc = if HOURGLASS_BASE[alpha][a] > 0.0 {
                    acc.add(qts[alpha][i])
                } else {
                    acc.sub(qts[alpha][i])
                };
            }
            force[i][a] = acc;
        }
    }
}

/// Adds the internal forces of `batches` into `f` (one block: no other thread touches its
/// nodes).
///
/// # Safety
/// `f` must be valid for every node index of the batches, and no other thread may access those
/// entries during the call.
#[inline(always)]
unsafe fn block_impl<const FMA: bool, const PHYSICAL: bool>(
    batches: &[ElementBatch],
    u: &[P3],
    f: *mut P3,
) {
    let mut fe = [[V::default(); 8]; 3];
    for b in batches {
        batch_forces::<FMA, PHYSICAL>(b, u, &mut fe);
        for l in 0..(b.count as usize) {
            for a in 0..8 {
                let dst = &mut *f.add(b.nodes[a][l] as usize);
                dst[0] += fe[0][a].0[l];
                dst[1] += fe[1][a].0[l];
                dst[2] += fe[2][a].0[l];
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn block_avx2<const PHYSICAL: bool>(batches: &[ElementBatch], u: &[P3], f: *mut P3) {
    block_impl::<true, PHYSICAL>(batches, u, f)
}

/// Whether the AVX2 + FMA path is used on this processor.
pub fn uses_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Adds the internal forces of a block of batches into `f`.
///
/// # Safety
/// As [`block_impl`]: valid indices, and exclusive access to the block's nodes.
pub unsafe fn add_block_forces(
    batches: &[ElementBatch],
    u: &[P3],
    f: *mut P3,
    physical: bool,
    avx2: bool,
) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        if physical {
            block_avx2::<true>(batches, u, f)
        } else {
            block_avx2::<false>(batches, u, f)
        }
        return;
    }
    let _ = avx2;
    if physical {
        block_impl::<false, true>(batches, u, f)
    } else {
        block_impl::<false, false>(batches, u, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::explicit::element::{
        one_point_forces, ElasticMaterial, Hourglass, KernelOptions, NODE_NATURAL,
    };

    /// The batched kernel (both code paths) against the scalar reference kernel on seeded random
    /// distorted elements and random displacements, including partial batches: agreement to
    /// 1e-12 of the largest force (different operation order and fused multiply-adds).
    #[test]
    fn batched_kernel_matches_the_scalar_reference() {
        let mat = ElasticMaterial {
            density_kg_per_m3: 7850.0,
            youngs_modulus_pa: 210e9,
            poisson_ratio: 0.3,
        };
        let mut seed: u64 = 0x9e3779b97f4a7c15;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for hourglass in [Hourglass::default(), Hourglass::Stiffness { kappa: 0.1 }] {
            let physical = matches!(hourglass, Hourglass::Physical { .. });
            for count in 1..=LANES {
                let mut nodes: Vec<P3> = Vec::new();
                let mut elements = Vec::new();
                for _ in 0..count {
                    let base = nodes.len();
                    for c in NODE_NATURAL {
                        nodes.push([
                            0.005 * (1.0 + c[0]) + 0.001 * rnd(),
                            0.004 * (1.0 + c[1]) + 0.001 * rnd(),
                            0.006 * (1.0 + c[2]) + 0.001 * rnd(),
                        ]);
                    }
                    let conn: [usize; 8] = std::array::from_fn(|a| base + a);
                    let x: [P3; 8] = std::array::from_fn(|a| nodes[base + a]);
                    elements.push(OnePointElement::new(conn, &x, &mat, hourglass).unwrap());
                }
                let u: Vec<P3> = (0..nodes.len())
                    .map(|_| [1e-5 * rnd(), 1e-5 * rnd(), 1e-5 * rnd()])
                    .collect();
                let mut reference = vec![[0.0; 3]; nodes.len()];
                let opts = KernelOptions {
                    physical_hourglass: physical,
                    ..Default::default()
                };
                for el in &elements {
                    let mut fe = [[0.0; 3]; 8];
                    one_point_forces::<false>(el, &u, &u, opts, &mut fe);
                    for a in 0..8 {
                        for i in 0..3 {
                            reference[el.nodes[a] as usize][i] += fe[a][i];
                        }
                    }
                }
                let scale = reference
                    .iter()
                    .flat_map(|p| p.iter())
                    .fold(0.0f64, |m, v| m.max(v.abs()));
                let batch = [ElementBatch::pack(&elements)];
                for avx2 in [false, uses_avx2()] {
                    let mut f = vec![[0.0; 3]; nodes.len()];
                    unsafe { add_block_forces(&batch, &u, f.as_mut_ptr(), physical, avx2) };
                    for (p, q) in f.iter().zip(&reference) {
                        for i in 0..3 {
                            assert!(
                                (p[i] - q[i]).abs() <= 1e-12 * scale,
                                "{hourglass:?} {count} {avx2}: {} vs {}",
                                p[i],
                                q[i]
                            );
                        }
                    }
                }
            }
        }
    }
}
