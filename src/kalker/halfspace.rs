//! Boundary-element discretisation of two identical elastic half-spaces (as in Kalker's CONTACT).
//!
//! The potential contact area is a rectangle divided into `nx x ny` equal rectangular elements
//! (`dx x dy`) carrying piecewise-constant tractions. Combined influence coefficients (displacement
//! difference of the two bodies at the centre of element I due to unit traction on element J) come
//! from integrating the Boussinesq-Cerruti point-load solutions over the element rectangle
//! (Love 1929; Johnson, *Contact Mechanics*, eqs. 2.19 and 3.25; Kalker 1990 section 5.2):
//!
//! * normal:     `A_nn = 1/(pi E*) I[1/r]`
//! * tangential: `A_xx = 1/(pi G) ((1-nu) I[1/r] + nu I[x^2/r^3])`,
//!   `A_yy = 1/(pi G) ((1-nu) I[1/r] + nu I[y^2/r^3])`, `A_xy = A_yx = nu/(pi G) I[x y/r^3]`
//!
//! where `I[f]` is the integral of f(x - x', y - y') over the source rectangle. Normal-tangential
//! coupling is zero for identical bodies ("quasi-identity"). The double integrals have closed
//! forms from antiderivatives F with `d^2F/dxdy = f`, combined at the four corners:
//! `I[1/r]: x asinh(y/|x|) + y asinh(x/|y|)`; `I[x^2/r^3]: y asinh(x/|y|)`;
//! `I[y^2/r^3]: x asinh(y/|x|)`; `I[x y/r^3]: -r`. (Terms depending on one coordinate only,
//! e.g. `x ln|x|`, cancel in the corner sum and are dropped, which removes the log singularities.)
//!
//! Influence coefficients depend only on the index offset (Toeplitz), so products with a traction
//! field are linear convolutions, evaluated by FFT with zero padding to `2nx x 2ny`.

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};
use std::f64::consts::PI;
use std::sync::Arc;

/// A uniform grid of rectangular elements covering the potential contact area.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Grid {
    /// Number of elements along x (rolling direction).
    pub nx: usize,
    /// Number of elements along y.
    pub ny: usize,
    /// Element size along x (m).
    pub dx_m: f64,
    /// Element size along y (m).
    pub dy_m: f64,
    /// x of the centre of the first column (m).
    pub x_first_m: f64,
    /// y of the centre of the first row (m).
    pub y_first_m: f64,
}

impl Grid {
    /// Grid of `nx x ny` elements covering `[-half_x, half_x] x [-half_y, half_y]`.
    pub fn centered(half_length_x_m: f64, half_length_y_m: f64, nx: usize, ny: usize) -> Grid {
        let dx_m = 2.0 * half_length_x_m / nx as f64;
        let dy_m = 2.0 * half_length_y_m / ny as f64;
        Grid {
            nx,
            ny,
            dx_m,
            dy_m,
            x_first_m: -half_length_x_m + 0.5 * dx_m,
            y_first_m: -half_length_y_m + 0.5 * dy_m,
        }
    }
    /// Number of elements.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }
    /// True for an empty grid.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Linear index of element (i along x, j along y); y runs fastest.
    pub fn index(&self, i: usize, j: usize) -> usize {
        i * self.ny + j
    }
    /// x of column i's centre (m).
    pub fn x_m(&self, i: usize) -> f64 {
        self.x_first_m + i as f64 * self.dx_m
    }
    /// y of row j's centre (m).
    pub fn y_m(&self, j: usize) -> f64 {
        self.y_first_m + j as f64 * self.dy_m
    }
    /// Element area (m^2).
    pub fn element_area_m2(&self) -> f64 {
        self.dx_m * self.dy_m
    }
}

/// `x asinh(y/|x|)`, with its limit 0 at x = 0.
fn x_asinh_y_over_x(x: f64, y: f64) -> f64 {
    if x == 0.0 {
        0.0
    } else {
        x * (y / x.abs()).asinh()
    }
}

/// Corner sum `F(x2,y2) - F(x1,y2) - F(x2,y1) + F(x1,y1)` over the source rectangle of size
/// `dx x dy` centred at offset (x, y) from the field point.
fn corner_sum(
    x_m: f64,
    y_m: f64,
    dx_m: f64,
    dy_m: f64,
    antiderivative: impl Fn(f64, f64) -> f64,
) -> f64 {
    let (x1, x2) = (x_m - 0.5 * dx_m, x_m + 0.5 * dx_m);
    let (y1, y2) = (y_m - 0.5 * dy_m, y_m + 0.5 * dy_m);
    antiderivative(x2, y2) - antiderivative(x1, y2) - antiderivative(x2, y1)
        + antiderivative(x1, y1)
}

/// `I[1/r]` over a `dx x dy` rectangle at offset (x, y) (Love 1929).
pub fn integral_inverse_distance(x_m: f64, y_m: f64, dx_m: f64, dy_m: f64) -> f64 {
    corner_sum(x_m, y_m, dx_m, dy_m, |x, y| {
        x_asinh_y_over_x(x, y) + x_asinh_y_over_x(y, x)
    })
}

/// `I[x^2/r^3]` over a `dx x dy` rectangle at offset (x, y).
pub fn integral_xx_over_r3(x_m: f64, y_m: f64, dx_m: f64, dy_m: f64) -> f64 {
    corner_sum(x_m, y_m, dx_m, dy_m, |x, y| x_asinh_y_over_x(y, x))
}

/// `I[y^2/r^3]` over a `dx x dy` rectangle at offset (x, y).
pub fn integral_yy_over_r3(x_m: f64, y_m: f64, dx_m: f64, dy_m: f64) -> f64 {
    corner_sum(x_m, y_m, dx_m, dy_m, x_asinh_y_over_x)
}

/// `I[x y/r^3]` over a `dx x dy` rectangle at offset (x, y).
pub fn integral_xy_over_r3(x_m: f64, y_m: f64, dx_m: f64, dy_m: f64) -> f64 {
    corner_sum(x_m, y_m, dx_m, dy_m, |x, y| -(x * x + y * y).sqrt())
}

/// Combined normal influence coefficient (m/Pa) at offset (x, y) = field - source.
pub fn normal_influence(x_m: f64, y_m: f64, grid: &Grid, combined_modulus_pa: f64) -> f64 {
    integral_inverse_distance(x_m, y_m, grid.dx_m, grid.dy_m) / (PI * combined_modulus_pa)
}

/// Combined tangential influence coefficients `(A_xx, A_xy, A_yy)` (m/Pa) at offset (x, y).
pub fn tangential_influence(
    x_m: f64,
    y_m: f64,
    grid: &Grid,
    shear_modulus_pa: f64,
    poisson_ratio: f64,
) -> [f64; 3] {
    let scale = 1.0 / (PI * shear_modulus_pa);
    let inverse_distance = integral_inverse_distance(x_m, y_m, grid.dx_m, grid.dy_m);
    [
        scale
            * ((1.0 - poisson_ratio) * inverse_distance
                + poisson_ratio * integral_xx_over_r3(x_m, y_m, grid.dx_m, grid.dy_m)),
        scale * poisson_ratio * integral_xy_over_r3(x_m, y_m, grid.dx_m, grid.dy_m),
        scale
            * ((1.0 - poisson_ratio) * inverse_distance
                + poisson_ratio * integral_yy_over_r3(x_m, y_m, grid.dx_m, grid.dy_m)),
    ]
}

/// A Toeplitz kernel tabulated on index offsets `(di, dj)`, `|di| < nx`, `|dj| < ny`.
#[derive(Debug, Clone)]
pub struct OffsetKernel {
    nx: usize,
    ny: usize,
    values: Vec<f64>,
}

impl OffsetKernel {
    /// Tabulates `value(di, dj)`.
    pub fn new(nx: usize, ny: usize, value: impl Fn(isize, isize) -> f64) -> OffsetKernel {
        let mut values = Vec::with_capacity((2 * nx - 1) * (2 * ny - 1));
        for di in -(nx as isize - 1)..=(nx as isize - 1) {
            for dj in -(ny as isize - 1)..=(ny as isize - 1) {
                values.push(value(di, dj));
            }
        }
        OffsetKernel { nx, ny, values }
    }
    /// Kernel value at offset (di, dj) = field - source.
    #[inline]
    pub fn at(&self, di: isize, dj: isize) -> f64 {
        let row = (di + self.nx as isize - 1) as usize;
        let col = (dj + self.ny as isize - 1) as usize;
        self.values[row * (2 * self.ny - 1) + col]
    }
    /// The contiguous run of values for offset `di` and `dj` from `-(ny-1)` to `ny-1`.
    #[inline]
    pub fn row(&self, di: isize) -> &[f64] {
        let row = (di + self.nx as isize - 1) as usize;
        let width = 2 * self.ny - 1;
        &self.values[row * width..(row + 1) * width]
    }
}

/// FFT machinery for linear convolutions on a grid, zero padded to `2nx x 2ny`.
pub struct Convolver {
    nx: usize,
    ny: usize,
    padded_x: usize,
    padded_y: usize,
    forward_x: Arc<dyn Fft<f64>>,
    inverse_x: Arc<dyn Fft<f64>>,
    forward_y: Arc<dyn Fft<f64>>,
    inverse_y: Arc<dyn Fft<f64>>,
}

impl Convolver {
    /// Plans the FFTs for an `nx x ny` grid.
    pub fn new(nx: usize, ny: usize) -> Convolver {
        let (padded_x, padded_y) = (2 * nx, 2 * ny);
        let mut planner = FftPlanner::new();
        Convolver {
            nx,
            ny,
            padded_x,
            padded_y,
            forward_x: planner.plan_fft_forward(padded_x),
            inverse_x: planner.plan_fft_inverse(padded_x),
            forward_y: planner.plan_fft_forward(padded_y),
            inverse_y: planner.plan_fft_inverse(padded_y),
        }
    }

    /// In-place 2D transform of a `padded_x x padded_y` array (y fastest).
    fn transform(&self, data: &mut [Complex<f64>], inverse: bool) {
        let (fft_x, fft_y) = if inverse {
            (&self.inverse_x, &self.inverse_y)
        } else {
            (&self.forward_x, &self.forward_y)
        };
        fft_y.process(data); // every contiguous row of length padded_y
        let mut transposed = vec![Complex::new(0.0, 0.0); data.len()];
        for i in 0..self.padded_x {
            for j in 0..self.padded_y {
                transposed[j * self.padded_x + i] = data[i * self.padded_y + j];
            }
        }
        fft_x.process(&mut transposed);
        for i in 0..self.padded_x {
            for j in 0..self.padded_y {
                data[i * self.padded_y + j] = transposed[j * self.padded_x + i];
            }
        }
    }

    /// Spectrum of a kernel, laid out circulantly so that the cyclic product equals the linear one.
    pub fn kernel_spectrum(&self, kernel: &OffsetKernel) -> Vec<Complex<f64>> {
        let mut data = vec![Complex::new(0.0, 0.0); self.padded_x * self.padded_y];
        for di in -(self.nx as isize - 1)..=(self.nx as isize - 1) {
            let row = di.rem_euclid(self.padded_x as isize) as usize;
            for dj in -(self.ny as isize - 1)..=(self.ny as isize - 1) {
                let col = dj.rem_euclid(self.padded_y as isize) as usize;
                data[row * self.padded_y + col] = Complex::new(kernel.at(di, dj), 0.0);
            }
        }
        self.transform(&mut data, false);
        data
    }

    /// Spectrum of a field given on the grid (zero padded).
    pub fn field_spectrum(&self, field: &[f64]) -> Vec<Complex<f64>> {
        let mut data = vec![Complex::new(0.0, 0.0); self.padded_x * self.padded_y];
        for i in 0..self.nx {
            for j in 0..self.ny {
                data[i * self.padded_y + j] = Complex::new(field[i * self.ny + j], 0.0);
            }
        }
        self.transform(&mut data, false);
        data
    }

    /// Back to the grid: inverse transform of a spectrum, normalised, cropped to `nx x ny`.
    pub fn to_field(&self, mut spectrum: Vec<Complex<f64>>) -> Vec<f64> {
        self.transform(&mut spectrum, true);
        let scale = 1.0 / (self.padded_x * self.padded_y) as f64;
        let mut field = vec![0.0; self.nx * self.ny];
        for i in 0..self.nx {
            for j in 0..self.ny {
                field[i * self.ny + j] = spectrum[i * self.padded_y + j].re * scale;
            }
        }
        field
    }

    /// Coupled products for a pair of fields sharing one FFT each way:
    /// `(u, v) = (Kxx * f + Kxy * g, Kxy * f + Kyy * g)`. The pair is packed as `f + i g`; with real
    /// fields, `F(k) = (P(k) + conj P(-k))/2` and `G(k) = (P(k) - conj P(-k))/(2i)`, and the real
    /// results come back as the real and imaginary parts of one inverse transform.
    pub fn convolve_pair(
        &self,
        spectra: &[Vec<Complex<f64>>; 3],
        field_x: &[f64],
        field_y: &[f64],
    ) -> [Vec<f64>; 2] {
        let (mx, my) = (self.padded_x, self.padded_y);
        let mut packed = vec![Complex::new(0.0, 0.0); mx * my];
        for i in 0..self.nx {
            for j in 0..self.ny {
                let k = i * self.ny + j;
                packed[i * my + j] = Complex::new(field_x[k], field_y[k]);
            }
        }
        self.transform(&mut packed, false);
        let [xx, xy, yy] = spectra;
        let mut product = vec![Complex::new(0.0, 0.0); mx * my];
        for i in 0..mx {
            let mirrored_i = (mx - i) % mx;
            for j in 0..my {
                let k = i * my + j;
                let mirrored = packed[mirrored_i * my + (my - j) % my].conj();
                let spectrum_x = (packed[k] + mirrored) * 0.5;
                let spectrum_y = (packed[k] - mirrored) * Complex::new(0.0, -0.5);
                let result_x = xx[k] * spectrum_x + xy[k] * spectrum_y;
                let result_y = xy[k] * spectrum_x + yy[k] * spectrum_y;
                product[k] = result_x + Complex::new(0.0, 1.0) * result_y;
            }
        }
        self.transform(&mut product, true);
        let scale = 1.0 / (mx * my) as f64;
        let mut out_x = vec![0.0; self.nx * self.ny];
        let mut out_y = vec![0.0; self.nx * self.ny];
        for i in 0..self.nx {
            for j in 0..self.ny {
                let value = product[i * my + j];
                out_x[i * self.ny + j] = value.re * scale;
                out_y[i * self.ny + j] = value.im * scale;
            }
        }
        [out_x, out_y]
    }

    /// `u_I = sum_J K(I - J) p_J` for one kernel spectrum.
    pub fn convolve(&self, kernel_spectrum: &[Complex<f64>], field: &[f64]) -> Vec<f64> {
        let mut spectrum = self.field_spectrum(field);
        for (value, kernel) in spectrum.iter_mut().zip(kernel_spectrum) {
            *value *= kernel;
        }
        self.to_field(spectrum)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_of_square_matches_love() {
        // Love (1929): at the centre of a square of side 2c, I[1/r] = 8 c ln(1 + sqrt 2).
        let value = integral_inverse_distance(0.0, 0.0, 2.0, 2.0);
        assert!((value - 8.0 * (1.0 + 2f64.sqrt()).ln()).abs() < 1e-12);
        // Far away the rectangle acts as a point load: I[1/r] -> area / r.
        let far = integral_inverse_distance(30.0, 40.0, 1.0, 0.5);
        assert!((far / (0.5 / 50.0) - 1.0).abs() < 1e-3);
        // I[x^2/r^3] + I[y^2/r^3] = I[1/r].
        let (x, y) = (1.3, -0.4);
        let sum = integral_xx_over_r3(x, y, 0.7, 0.9) + integral_yy_over_r3(x, y, 0.7, 0.9);
        assert!((sum - integral_inverse_distance(x, y, 0.7, 0.9)).abs() < 1e-12);
        // Far field of I[x y / r^3] -> area x y / r^3.
        let far_xy = integral_xy_over_r3(30.0, 40.0, 1.0, 0.5);
        assert!((far_xy / (0.5 * 1200.0 / 125000.0) - 1.0).abs() < 1e-3);
    }

    #[test]
    fn packed_pair_equals_separate_products() {
        let (nx, ny) = (6, 5);
        let kernel = |shift: f64| {
            OffsetKernel::new(nx, ny, move |di, dj| {
                1.0 / (1.0 + shift + (di * di + dj * dj) as f64) + 0.05 * (di * dj) as f64
            })
        };
        let kernels = [kernel(0.0), kernel(1.0), kernel(2.5)];
        let convolver = Convolver::new(nx, ny);
        let spectra = [
            convolver.kernel_spectrum(&kernels[0]),
            convolver.kernel_spectrum(&kernels[1]),
            convolver.kernel_spectrum(&kernels[2]),
        ];
        let fx: Vec<f64> = (0..nx * ny).map(|k| ((k * 5) % 7) as f64 - 2.0).collect();
        let fy: Vec<f64> = (0..nx * ny).map(|k| ((k * 3) % 11) as f64 * 0.3).collect();
        let [ux, uy] = convolver.convolve_pair(&spectra, &fx, &fy);
        let sum = |a: Vec<f64>, b: Vec<f64>| -> Vec<f64> {
            a.iter().zip(&b).map(|(x, y)| x + y).collect()
        };
        let expected_x = sum(
            convolver.convolve(&spectra[0], &fx),
            convolver.convolve(&spectra[1], &fy),
        );
        let expected_y = sum(
            convolver.convolve(&spectra[1], &fx),
            convolver.convolve(&spectra[2], &fy),
        );
        for k in 0..nx * ny {
            assert!((ux[k] - expected_x[k]).abs() < 1e-10 && (uy[k] - expected_y[k]).abs() < 1e-10);
        }
    }

    #[test]
    fn fft_convolution_equals_direct_sum() {
        let (nx, ny) = (5, 7);
        let kernel = OffsetKernel::new(nx, ny, |di, dj| {
            1.0 / (1.0 + (di * di + 2 * dj * dj) as f64) + 0.1 * di as f64
        });
        let field: Vec<f64> = (0..nx * ny).map(|k| ((k * 7) % 11) as f64 - 3.0).collect();
        let convolver = Convolver::new(nx, ny);
        let fast = convolver.convolve(&convolver.kernel_spectrum(&kernel), &field);
        for i in 0..nx {
            for j in 0..ny {
                let mut direct = 0.0;
                for k in 0..nx {
                    for l in 0..ny {
                        direct += kernel.at(i as isize - k as isize, j as isize - l as isize)
                            * field[k * ny + l];
                    }
                }
                assert!((fast[i * ny + j] - direct).abs() < 1e-10);
            }
        }
    }
}
