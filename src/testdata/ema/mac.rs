//! The modal assurance criterion (Allemang & Brown, "A correlation coefficient for modal vector
//! analysis", IMAC I, 1982): `MAC(a, b) = |a^H b|^2 / ((a^H a)(b^H b))`, 1 for proportional shapes
//! (any complex scale), 0 for orthogonal ones.

use rustfft::num_complex::Complex;

/// MAC of two shapes of equal length; 0 when either is zero.
pub fn mac(a: &[Complex<f64>], b: &[Complex<f64>]) -> f64 {
    assert_eq!(a.len(), b.len(), "shapes at the same DOFs");
    let cross: Complex<f64> = a.iter().zip(b).map(|(x, y)| x.conj() * y).sum();
    let (aa, bb): (f64, f64) = (
        a.iter().map(|x| x.norm_sqr()).sum(),
        b.iter().map(|x| x.norm_sqr()).sum(),
    );
    if aa > 0.0 && bb > 0.0 {
        cross.norm_sqr() / (aa * bb)
    } else {
        0.0
    }
}

/// MAC of `a` with a subspace (a doublet of an axisymmetric body: two modes of one frequency
/// whose every combination is a mode): `|Q^H a|^2 / (a^H a)` with Q an orthonormal basis of
/// `basis` (Gram-Schmidt), the MAC of `a` with its best approximation in the subspace. With one
/// basis vector it is the plain MAC.
pub fn subspace_mac(a: &[Complex<f64>], basis: &[Vec<Complex<f64>>]) -> f64 {
    let aa: f64 = a.iter().map(|x| x.norm_sqr()).sum();
    if aa == 0.0 {
        return 0.0;
    }
    let mut orthonormal: Vec<Vec<Complex<f64>>> = Vec::new();
    for v in basis {
        assert_eq!(v.len(), a.len(), "shapes at the same DOFs");
        let mut w = v.clone();
        for q in &orthonormal {
            let projection: Complex<f64> = q.iter().zip(&w).map(|(x, y)| x.conj() * y).sum();
            for (wi, qi) in w.iter_mut().zip(q) {
                *wi -= projection * qi;
            }
        }
        let norm = w.iter().map(|x| x.norm_sqr()).sum::<f64>().sqrt();
        // A vector (nearly) inside the span of the previous ones adds nothing.
        let original = v.iter().map(|x| x.norm_sqr()).sum::<f64>().sqrt();
        if norm > 1e-10 * original && norm > 0.0 {
            orthonormal.push(w.iter().map(|x| x / norm).collect());
        }
    }
    let captured: f64 = orthonormal
        .iter()
        .map(|q| {
            q.iter()
                .zip(a)
                .map(|(x, y)| x.conj() * y)
                .sum::<Complex<f64>>()
                .norm_sqr()
        })
        .sum();
    captured / aa
}

#[cfg(test)]
mod tests {
    use super::*;

    fn real(v: &[f64]) -> Vec<Complex<f64>> {
        v.iter().map(|&x| Complex::new(x, 0.0)).collect()
    }

    #[test]
    fn identical_shapes_give_one_and_orthogonal_shapes_zero() {
        let a = real(&[1.0, 0.8, 0.5, 0.2]);
        assert!((mac(&a, &a) - 1.0).abs() < 1e-15);
        // Any complex scale of a shape is the same shape.
        let scaled: Vec<Complex<f64>> = a.iter().map(|x| x * Complex::new(-3.0, 2.0)).collect();
        assert!((mac(&a, &scaled) - 1.0).abs() < 1e-15);
        let b = real(&[0.8, -1.0, 0.2, -0.5]); // a . b = 0.8 - 0.8 + 0.1 - 0.1 = 0
        assert!(mac(&a, &b).abs() < 1e-30);
        assert_eq!(mac(&a, &real(&[0.0; 4])), 0.0);
        // Partial correlation: cos^2 of the angle between real vectors.
        let (x, y) = (real(&[1.0, 0.0]), real(&[1.0, 1.0]));
        assert!((mac(&x, &y) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn subspace_mac_finds_a_shape_inside_a_doublet() {
        // cos(3 theta) and sin(3 theta) at 8 points; a rotated pattern is a combination of both.
        let points: Vec<f64> = (0..8)
            .map(|k| k as f64 * std::f64::consts::TAU / 8.0)
            .collect();
        let cos: Vec<f64> = points.iter().map(|t| (3.0 * t).cos()).collect();
        let sin: Vec<f64> = points.iter().map(|t| (3.0 * t).sin()).collect();
        let rotated: Vec<f64> = points.iter().map(|t| (3.0 * (t - 0.4)).cos()).collect();
        let (cos, sin, rotated) = (real(&cos), real(&sin), real(&rotated));
        assert!(mac(&rotated, &cos) < 0.9, "one member alone misses it");
        let both = subspace_mac(&rotated, &[cos.clone(), sin.clone()]);
        assert!((both - 1.0).abs() < 1e-12, "{both}");
        // One vector: the plain MAC; a repeated vector adds nothing.
        assert!(
            (subspace_mac(&rotated, std::slice::from_ref(&cos)) - mac(&rotated, &cos)).abs()
                < 1e-12
        );
        assert!(
            (subspace_mac(&rotated, &[cos.clone(), cos.clone()]) - mac(&rotated, &cos)).abs()
                < 1e-12
        );
    }
}
