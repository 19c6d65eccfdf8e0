//! What the band solve takes and returns: its options, the modes and the solution record.

use serde::Serialize;

/// Options of the band solve.
#[derive(Clone, Debug)]
pub struct ModalOptions {
    /// Upper band edge (Hz).
    pub fmax_hz: f64,
    /// Modes below this frequency (Hz) are flagged rigid (free-free rigid-body motion).
    pub rigid_below_hz: f64,
    /// Shift magnitude (Hz): `sigma = -(2 pi shift_hz)²`; `None` chooses `max(fmax / 20, 10)`.
    pub shift_hz: Option<f64>,
    /// Largest relative residual accepted for a returned mode.
    pub residual_tolerance: f64,
    /// Largest Krylov basis (vectors) before giving up.
    pub max_basis: usize,
    /// Block size of the block Lanczos (columns per operator application).
    pub block_size: usize,
    /// Check completeness with a Sturm count: the negative pivots of the LDLᵀ of
    /// `K - w_max² M` (Sylvester's law of inertia, M positive definite) are the eigenvalues
    /// below `fmax`, which must equal the modes found. A second (simplicial) factorisation.
    pub sturm_check: bool,
    /// Slices of the band, one shift each (spectrum slicing): the first below the spectrum,
    /// the others in the middle of their slice (edges equally spaced in frequency). More
    /// slices mean more factorisations but smaller Krylov bases (orthogonalisation grows with
    /// the square of the basis): for wide bands with many modes. 1..=[`crate::modal::slice::MAX_SLICES`].
    pub slices: usize,
    /// Purify the Ritz vectors by one more solve, `y = Op x` (the textbook way), instead of
    /// from the basis through the Lanczos relation (the default: the same vectors to rounding,
    /// without a solve of every wanted column; [`crate::modal::lanczos`]). For comparisons.
    pub purify_by_solve: bool,
}

impl Default for ModalOptions {
    fn default() -> Self {
        ModalOptions {
            fmax_hz: 10_000.0,
            rigid_below_hz: 1.0,
            shift_hz: None,
            // 1e-8: the acceptance bound; purified shift-invert Ritz vectors reach
            // 1e-10..1e-13 on the meshes of the tests.
            residual_tolerance: 1e-8,
            max_basis: 4000,
            // 16: on the 92 k dof wheel at 10 kHz, 29.9 s against 32.5 s with 8 and 44.8 s
            // with 32 (basis 592 / 504 / 832), measured 2026-11-23.
            block_size: 16,
            sturm_check: true,
            slices: 1,
            purify_by_solve: false,
        }
    }
}

/// One mode.
#[derive(Clone, Debug, Serialize)]
pub struct Mode {
    /// Frequency (Hz); negative round-off eigenvalues of rigid modes give `-sqrt(|w²|)/2pi`.
    pub frequency_hz: f64,
    /// Eigenvalue `w²` (rad²/s²).
    pub eigenvalue: f64,
    /// Relative residual (see the module docs).
    pub residual: f64,
    /// What double precision lets that residual reach for this mode
    /// ([`crate::modal::residual`]).
    pub residual_floor: f64,
    /// Rigid-body mode (frequency below `rigid_below_hz`).
    pub rigid: bool,
    /// Eigenvector in the reduced dofs, M-normalised (`xᵀ M x = 1`).
    #[serde(skip)]
    pub vector: Vec<f64>,
}

/// Result of a band solve.
#[derive(Clone, Debug, Serialize)]
pub struct ModalSolution {
    /// Modes, ascending frequency.
    pub modes: Vec<Mode>,
    /// Shift `sigma` below the spectrum (rad²/s²), the first slice's.
    pub shift: f64,
    /// The shift of every slice solved (rad²/s²; slices without modes are skipped).
    pub shifts: Vec<f64>,
    /// Final Krylov basis size.
    pub basis_size: usize,
    /// Block size.
    pub block_size: usize,
    /// Blocks applied (operator applications of `block_size` columns).
    pub blocks: usize,
    /// Factorisation time (s).
    pub factor_seconds: f64,
    /// Total solve time incl. factorisation (s).
    pub solve_seconds: f64,
    /// Eigenvalues below `fmax` by the Sturm count (None: not checked).
    pub sturm_count: Option<usize>,
}
