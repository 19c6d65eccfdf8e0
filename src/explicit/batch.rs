//! The fast path of the one-point element: four elements at a time, one per SIMD lane
//! (structure of arrays), for the common case of elastic elements with stiffness-type
//! hourglass control and no element damping. It computes exactly what
//! [`super::element::one_point_forces`] computes (the slow, trusted reference it is tested
//! against on random distorted elements) and is compiled twice: with AVX2 + FMA, chosen at run
//! time when the processor has them, and for the baseline target.

// Index loops mirror the tensor notation of the equations (the project's style for kernels);
// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

use super::element::OnePointElement;
#[cfg(test)]
use super::element::HOURGLASS_BASE;
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

/// Four lanes of f32: the element data that [`OnePointElement`] rounds to single precision,
/// widened to [`V`] when used.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(16))]
pub struct VF(pub [f32; LANES]);

impl VF {
    #[inline(always)]
    fn widen(self) -> V {
        V([
            self.0[0] as f64,
            self.0[1] as f64,
            self.0[2] as f64,
            self.0[3] as f64,
        ])
    }
}

/// Four elements' data, lane l = element `4 k + l` (padding lanes repeat a real element's nodes
/// with zero stiffness, so they add exact zeros to nodes their own block owns). 1376 bytes, 344
/// per element: the single-precision values of [`OnePointElement`] in f32, the hourglass
/// vectors in f64.
#[derive(Clone, Debug)]
#[repr(C, align(32))]
pub struct ElementBatch {
    /// `F0^-1 sum_b h_alpha,b X_b` (f64: rigid rotations rely on it to rounding).
    pub hourglass_ref: [[V; 3]; 4],
    /// Mean gradients `b_a` per direction of nodes 0..=6; node 7's is minus their sum.
    pub grad: [[VF; 7]; 3],
    /// `F0 - I`.
    pub stretch_delta: [[VF; 3]; 3],
    /// Physical form: reference axes (columns of J at the centre).
    pub axes_ref: [[VF; 3]; 3],
    /// Physical form: stiffness per mode and axis (the isotropic forms use `isotropic_coef`).
    pub axis_coef: [[VF; 3]; 4],
    /// Isotropic (Flanagan-Belytschko) coefficient.
    pub isotropic_coef: VF,
    /// `lambda V0`.
    pub lambda_vol: VF,
    /// `2 mu V0`.
    pub two_mu_vol: VF,
    /// Nodes per lane.
    pub nodes: [[u32; LANES]; 8],
}

impl ElementBatch {
    /// Packs up to four elements.
    pub fn pack(elements: &[OnePointElement]) -> ElementBatch {
        assert!(!elements.is_empty() && elements.len() <= LANES);
        let mut b = ElementBatch {
            hourglass_ref: [[V::default(); 3]; 4],
            grad: [[VF::default(); 7]; 3],
            stretch_delta: [[VF::default(); 3]; 3],
            axes_ref: [[VF::default(); 3]; 3],
            axis_coef: [[VF::default(); 3]; 4],
            isotropic_coef: VF::default(),
            lambda_vol: VF::default(),
            two_mu_vol: VF::default(),
            nodes: [[0; LANES]; 8],
        };
        // The element's values are single-precision numbers already (rounded in
        // `OnePointElement::new`): these casts are exact.
        let single = |x: f64| x as f32;
        for l in 0..LANES {
            let (el, real) = match elements.get(l) {
                Some(e) => (e, true),
                None => (&elements[0], false),
            };
            let s = if real { 1.0 } else { 0.0 };
            for a in 0..8 {
                b.nodes[a][l] = el.nodes[a];
            }
            for j in 0..3 {
                for a in 0..7 {
                    b.grad[j][a].0[l] = single(el.grad[j][a]);
                }
                for i in 0..3 {
                    b.stretch_delta[i][j].0[l] = single(el.stretch_delta[i][j]);
                }
            }
            for alpha in 0..4 {
                for j in 0..3 {
                    b.hourglass_ref[alpha][j].0[l] = el.hourglass_ref[alpha][j];
                    b.axis_coef[alpha][j].0[l] = single(s * el.hourglass_axis_coef[alpha][j]);
                }
            }
            for r in 0..3 {
                for j in 0..3 {
                    // Padding lanes repeat a real element's axes, so the normalisation stays
                    // finite.
                    b.axes_ref[r][j].0[l] = single(el.axes_ref[r][j]);
                }
            }
            b.isotropic_coef.0[l] = single(s * el.hourglass_coef);
            b.lambda_vol.0[l] = single(s * el.lambda_vol);
            b.two_mu_vol.0[l] = single(s * el.two_mu_vol);
        }
        b
    }
}

/// Sums `sum_a h_alpha,a x_a` of eight nodal values against the four hourglass base vectors
/// ([`HOURGLASS_BASE`]: the products xi eta, eta zeta, xi zeta and xi eta zeta of the nodes'
/// natural coordinates, VTK order), by a butterfly over the three natural directions:
/// 18 additions instead of 28.
#[inline(always)]
fn hourglass_sums(x: &[V; 8]) -> [V; 4] {
    // Along xi on the four edges (eta, zeta) = (-,-), (+,-), (-,+), (+,+): the differences
    // carry the xi factor, the sums do not.
    let d_mm = x[1].sub(x[0]);
    let d_pm = x[2].sub(x[3]);
    let d_mp = x[5].sub(x[4]);
    let d_pp = x[6].sub(x[7]);
    let s_mm = x[1].add(x[0]);
    let s_pm = x[2].add(x[3]);
    let s_mp = x[5].add(x[4]);
    let s_pp = x[6].add(x[7]);
    // Along eta on the two faces zeta = -, +: xi eta, xi and eta factors.
    let xi_eta_m = d_pm.sub(d_mm);
    let xi_eta_p = d_pp.sub(d_mp);
    let xi_m = d_pm.add(d_mm);
    let xi_p = d_pp.add(d_mp);
    let eta_m = s_pm.sub(s_mm);
    let eta_p = s_pp.sub(s_mp);
    // Along zeta.
    [
        xi_eta_p.add(xi_eta_m),
        eta_p.sub(eta_m),
        xi_p.sub(xi_m),
        xi_eta_p.sub(xi_eta_m),
    ]
}

/// The transpose of [`hourglass_sums`]: `x_a = sum_alpha h_alpha,a g_alpha` (14 additions
/// instead of 24).
#[inline(always)]
fn hourglass_spread(g: &[V; 4]) -> [V; 8] {
    let g0_minus_g3 = g[0].sub(g[3]);
    let g0_plus_g3 = g[0].add(g[3]);
    let g1_plus_g2 = g[1].add(g[2]);
    let g1_minus_g2 = g[1].sub(g[2]);
    let zero = V::default();
    [
        g1_plus_g2.add(g0_minus_g3),
        g1_minus_g2.sub(g0_minus_g3),
        g0_minus_g3.sub(g1_plus_g2),
        zero.sub(g1_minus_g2.add(g0_minus_g3)),
        g0_plus_g3.sub(g1_plus_g2),
        zero.sub(g1_minus_g2.add(g0_plus_g3)),
        g1_plus_g2.add(g0_plus_g3),
        g1_minus_g2.sub(g0_plus_g3),
    ]
}

/// Internal forces of a batch, `force[i][a]` per lane (the caller scatters them).
///
/// The work is arranged component by component (`i` = x, y, z) wherever the equations allow, so
/// that few values are live at once and the four-lane vectors stay in registers.
///
/// Kept in one piece: the eight-lane kernel must stay in one function for the compiler to keep its
/// lanes in registers.
#[inline(always)]
fn batch_forces<const FMA: bool, const PHYSICAL: bool>(
    b: &ElementBatch,
    u: &[P3],
    force: &mut [[V; 8]; 3],
) {
    // Gradients widened to f64; node 7's is minus the sum of the others, summed in the order
    // of `OnePointElement::new`, so that both give bit-identical values.
    let mut grad = [[V::default(); 8]; 3];
    for j in 0..3 {
        let mut sum = V::default();
        for a in 0..7 {
            grad[j][a] = b.grad[j][a].widen();
            sum = sum.add(grad[j][a]);
        }
        grad[j][7] = V::default().sub(sum);
    }
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
    // H_ij = sum_a u_ai b_aj, and the hourglass sums w_alpha,i = sum_a h_alpha,a u_ai.
    let mut h = [[V::default(); 3]; 3];
    let mut w = [[V::default(); 4]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let mut acc = ue[i][0].mul(grad[j][0]);
            for a in 1..8 {
                acc = ue[i][a].madd::<FMA>(grad[j][a], acc);
            }
            h[i][j] = acc;
        }
        w[i] = hourglass_sums(&ue[i]);
    }
    // F = F0 + H = I + d; E = (F^T F - F0^T F0) / 2 = (H + H^T) / 2 + (K^T H + H^T K) / 2 with
    // K = delta + H / 2 (see `OnePointElement`).
    let half = V::splat(0.5);
    let mut d = [[V::default(); 3]; 3];
    let mut k = [[V::default(); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let delta = b.stretch_delta[i][j].widen();
            d[i][j] = h[i][j].add(delta);
            k[i][j] = h[i][j].madd::<FMA>(half, delta);
        }
    }
    let mut e = [[V::default(); 3]; 3];
    for i in 0..3 {
        for j in i..3 {
            let mut acc = h[i][j].add(h[j][i]);
            for m in 0..3 {
                acc = k[m][i].madd::<FMA>(h[m][j], acc);
                acc = h[m][i].madd::<FMA>(k[m][j], acc);
            }
            e[i][j] = acc.mul(half);
            e[j][i] = e[i][j];
        }
    }
    let tr = e[0][0].add(e[1][1]).add(e[2][2]);
    let two_mu_vol = b.two_mu_vol.widen();
    let ltr = b.lambda_vol.widen().mul(tr);
    let mut s = [[V::default(); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            s[i][j] = two_mu_vol.mul(e[i][j]);
        }
        s[i][i] = s[i][i].add(ltr);
    }
    // Hourglass, rearranged so that g_alpha,a = h_alpha,a - hX_alpha . b_a is never formed:
    //   q_alpha = w_alpha - H hX_alpha,
    //   f_a += sum_alpha g_alpha,a qt_alpha = sum_alpha h_alpha,a qt_alpha - Q b_a,
    //   with Q = sum_alpha qt_alpha (x) hX_alpha, folded into the stress term as (P - Q) b_a.
    let mut axes = [[V::default(); 3]; 3];
    if PHYSICAL {
        // Current axes t_r = F t_r0 = t_r0 + d t_r0, normalised.
        for r in 0..3 {
            let t0 = b.axes_ref[r].map(VF::widen);
            for i in 0..3 {
                let mut acc = t0[i];
                for j in 0..3 {
                    acc = d[i][j].madd::<FMA>(t0[j], acc);
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
    // qt[i][alpha]: generalised hourglass force of mode alpha, component i.
    let mut qt = [[V::default(); 4]; 3];
    for alpha in 0..4 {
        let hx = b.hourglass_ref[alpha];
        let mut q = [V::default(); 3];
        for i in 0..3 {
            let mut hh = h[i][0].mul(hx[0]);
            hh = h[i][1].madd::<FMA>(hx[1], hh);
            hh = h[i][2].madd::<FMA>(hx[2], hh);
            q[i] = w[i][alpha].sub(hh);
        }
        if PHYSICAL {
            let mut acc = [V::default(); 3];
            for r in 0..3 {
                let t = axes[r];
                let mut pr = q[0].mul(t[0]);
                pr = q[1].madd::<FMA>(t[1], pr);
                pr = q[2].madd::<FMA>(t[2], pr);
                let c = b.axis_coef[alpha][r].widen().mul(pr);
                for i in 0..3 {
                    acc[i] = c.madd::<FMA>(t[i], acc[i]);
                }
            }
            for i in 0..3 {
                qt[i][alpha] = acc[i];
            }
        } else {
            let coef = b.isotropic_coef.widen();
            for i in 0..3 {
                qt[i][alpha] = q[i].mul(coef);
            }
        }
    }
    for i in 0..3 {
        // Row i of M = P - Q, with P = F S = (I + d) S.
        let mut m = [V::default(); 3];
        for j in 0..3 {
            let mut acc = s[i][j];
            for k in 0..3 {
                acc = d[i][k].madd::<FMA>(s[k][j], acc);
            }
            let mut qsum = qt[i][0].mul(b.hourglass_ref[0][j]);
            for alpha in 1..4 {
                qsum = qt[i][alpha].madd::<FMA>(b.hourglass_ref[alpha][j], qsum);
            }
            m[j] = acc.sub(qsum);
        }
        let spread = hourglass_spread(&qt[i]);
        for a in 0..8 {
            let mut acc = m[0].madd::<FMA>(grad[0][a], spread[a]);
            acc = m[1].madd::<FMA>(grad[1][a], acc);
            acc = m[2].madd::<FMA>(grad[2][a], acc);
            force[i][a] = acc;
        }
    }
}

/// How many batches ahead [`block_impl`] asks for the element data: the kernel streams every
/// element's ~0.5 kB once per step, and a model larger than the last-level cache waits on memory
/// unless the loads are started early (measured on a 100 000-element block, 1 thread: the
/// element loop took ~105 ns per element without, ~55 ns when the data fits in L2).
const PREFETCH_BATCHES_AHEAD: usize = 2;

/// Starts loading one batch's data into the cache.
#[inline(always)]
fn prefetch_batch(b: &ElementBatch) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let start = b as *const ElementBatch as *const i8;
        let mut offset = 0;
        while offset < std::mem::size_of::<ElementBatch>() {
            // SAFETY: prefetching is a hint that never faults; the address lies inside `b`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(start.add(offset)) };
            offset += 64;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = b;
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
    for (k, b) in batches.iter().enumerate() {
        if let Some(ahead) = batches.get(k + PREFETCH_BATCHES_AHEAD) {
            prefetch_batch(ahead);
        }
        batch_forces::<FMA, PHYSICAL>(b, u, &mut fe);
        // All four lanes: padding lanes add exact zeros (zero stiffness) to nodes of this block.
        for l in 0..LANES {
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

    /// Seeded uniform numbers in [-0.5, 0.5) (xorshift64).
    fn xorshift(seed: u64) -> impl FnMut() -> f64 {
        let mut rng = crate::random::XorShift64(seed);
        move || rng.centred_uniform()
    }

    /// The butterflies against the base vectors they stand for, on seeded random values.
    #[test]
    fn hourglass_butterflies_match_the_base_vectors() {
        let mut rnd = xorshift(0x2545f4914f6cdd1d);
        for _ in 0..20 {
            let x: [V; 8] = std::array::from_fn(|_| V([rnd(), rnd(), rnd(), rnd()]));
            let sums = hourglass_sums(&x);
            let g: [V; 4] = std::array::from_fn(|_| V([rnd(), rnd(), rnd(), rnd()]));
            let spread = hourglass_spread(&g);
            for l in 0..LANES {
                for alpha in 0..4 {
                    let direct: f64 = (0..8).map(|a| HOURGLASS_BASE[alpha][a] * x[a].0[l]).sum();
                    // Sums of eight numbers below 0.5 in another order: a few ulps of 4.
                    assert!((sums[alpha].0[l] - direct).abs() < 1e-14, "sum {alpha}");
                }
                for a in 0..8 {
                    let direct: f64 = (0..4).map(|al| HOURGLASS_BASE[al][a] * g[al].0[l]).sum();
                    assert!((spread[a].0[l] - direct).abs() < 1e-14, "spread {a}");
                }
            }
        }
    }

    /// Single-precision element data must not cost the exact invariances: a small element at
    /// a wheel's rim (0.46 m from the axis, 1 mm size), turned rigidly by 170 degrees about the
    /// axle and carried 1.4 m along the track, gets no force from the batched kernel (both
    /// code paths, both hourglass forms). Without the F0 term (`stretch_delta` zeroed) the
    /// rounded gradients give 4e-3 N here, 2e-8 of the unit-strain force; with it what is left
    /// is f64 cancellation in `sum_a u_a b_a` with |u| ~ 1 m against 1 mm elements, ~1e-12,
    /// hence the bound 1e-9.
    #[test]
    fn rigid_motion_at_a_wheel_rim_gives_no_force() {
        let mat = ElasticMaterial {
            density_kg_per_m3: 7850.0,
            youngs_modulus_pa: 210e9,
            poisson_ratio: 0.3,
        };
        let size_m = 1e-3;
        let mut nodes: Vec<P3> = Vec::new();
        let mut elements_iso = Vec::new();
        let mut elements_phys = Vec::new();
        for e in 0..LANES {
            let base = nodes.len();
            let angle0 = 0.05 * e as f64;
            for (a, c) in NODE_NATURAL.iter().enumerate() {
                // A slightly distorted brick near radius 0.46 m.
                let r = 0.46 + 0.5 * size_m * (1.0 + c[0]) + 1e-4 * (a % 3) as f64;
                let t = angle0 + 0.5 * size_m * (1.0 + c[1]) / 0.46;
                let z = 0.5 * size_m * (1.0 + c[2]) + 5e-5 * (a % 2) as f64;
                nodes.push([r * t.cos(), r * t.sin(), z]);
            }
            let conn: [usize; 8] = std::array::from_fn(|a| base + a);
            let x: [P3; 8] = std::array::from_fn(|a| nodes[base + a]);
            elements_iso.push(
                OnePointElement::new(conn, &x, &mat, Hourglass::Stiffness { kappa: 0.1 }).unwrap(),
            );
            elements_phys.push(OnePointElement::new(conn, &x, &mat, Hourglass::default()).unwrap());
        }
        let (c, s) = (170f64.to_radians().cos(), 170f64.to_radians().sin());
        let u: Vec<P3> = nodes
            .iter()
            .map(|p| {
                [
                    c * p[0] - s * p[1] - p[0] + 1.4,
                    s * p[0] + c * p[1] - p[1],
                    0.0,
                ]
            })
            .collect();
        let unit_strain_force_n = mat.youngs_modulus_pa * size_m * size_m;
        for (elements, physical) in [(&elements_iso, false), (&elements_phys, true)] {
            let batch = [ElementBatch::pack(elements)];
            for avx2 in [false, uses_avx2()] {
                let mut f = vec![[0.0; 3]; nodes.len()];
                unsafe { add_block_forces(&batch, &u, f.as_mut_ptr(), physical, avx2) };
                let worst = f
                    .iter()
                    .flat_map(|p| p.iter())
                    .fold(0.0f64, |m, v| m.max(v.abs()));
                assert!(
                    worst < 1e-9 * unit_strain_force_n,
                    "physical {physical}, avx2 {avx2}: {worst} N"
                );
            }
        }
    }

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
        let mut rnd = xorshift(0x9e3779b97f4a7c15);
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
