//! [`MassMatrixLu`](super::mass_matrix_lu::MassMatrixLu)'s factorizations and solves for a
//! dimension known at compile time (gymfleet patch 34, see `PATCHES.md`).
//!
//! A locomotion robot's mass matrix has 6 to 30 rows, refactorized at every substep. The
//! generic loops (in `mass_matrix_lu.rs`) run inner loops of a few iterations whose slicing
//! and bounds checks cost more than their multiply-adds: HalfCheetah's 9 × 9 `L·D·Lᵀ` took
//! about 2 700 instructions. These kernels are the same loops, with the same operations in
//! the same order (so the same bits), written for a constant `N`, which the compiler unrolls
//! and checks once. `with_fixed_dim!` picks the kernel for `n ≤ 32`; larger matrices keep
//! the generic loops.

use crate::math::Real;

/// The largest dimension with a fixed-size kernel: the last of `with_fixed_dim!`'s arms.
#[cfg(test)]
pub(super) const MAX_FIXED_DIM: usize = 32;

/// `Some($call::<N>($args))` for the constant `N` equal to `$n`, or `None` when `$n` is 0 or
/// larger than 32.
macro_rules! with_fixed_dim {
    ($n:expr, $call:ident $args:tt) => {{
        with_fixed_dim!(@arms $n, $call, $args,
            1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16
            17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32)
    }};
    (@arms $n:expr, $f:ident, $args:tt, $($dim:literal)*) => {
        match $n {
            $($dim => Some(
                $crate::dynamics::joint::multibody_joint::mass_matrix_fixed::$f::<$dim> $args
            ),)*
            _ => None,
        }
    };
}
pub(super) use with_fixed_dim;

/// `L·D·Lᵀ` of the column-major `N × N` matrix in `lu` (its upper triangle), in place, as
/// `MassMatrixLu::factorize_symmetric_leading` lays it out: row `j` of `L` above the diagonal
/// of column `j`, `D` on the diagonal. False, with `lu` partly overwritten, if a pivot is not
/// positive (or not finite).
#[inline(never)]
pub(super) fn factorize_symmetric<const N: usize>(lu: &mut [Real]) -> bool {
    let lu = &mut lu[..N * N];
    for j in 0..N {
        // `y_k = A[k, j] − Σ_{m<k} L[k, m]·y_m`, in place of `A[k, j]`.
        for k in 0..j {
            let mut y = lu[j * N + k];
            for m in 0..k {
                y -= lu[k * N + m] * lu[j * N + m];
            }
            lu[j * N + k] = y;
        }
        // `L[j, k] = y_k / d_k` and `d_j = A[j, j] − Σ_k y_k·L[j, k]`.
        let mut d = lu[j * N + j];
        for k in 0..j {
            let y = lu[j * N + k];
            let l = y / lu[k * N + k];
            d -= y * l;
            lu[j * N + k] = l;
        }
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        lu[j * N + j] = d;
    }
    true
}

/// `x ← A⁻¹·x` with the `L·D·Lᵀ` factors of [`factorize_symmetric`].
#[inline(never)]
pub(super) fn solve_symmetric<const N: usize>(lu: &[Real], x: &mut [Real]) {
    let (lu, x) = (&lu[..N * N], &mut x[..N]);
    for j in 0..N {
        let mut y = x[j];
        for k in 0..j {
            y -= lu[j * N + k] * x[k];
        }
        x[j] = y;
    }
    for j in 0..N {
        x[j] /= lu[j * N + j];
    }
    for i in (0..N).rev() {
        let xi = x[i];
        if xi != 0.0 {
            for k in 0..i {
                x[k] -= lu[i * N + k] * xi;
            }
        }
    }
}

/// Doolittle LU with partial row pivoting of the column-major `N × N` matrix in `lu`, in
/// place: `L` (unit diagonal) below the diagonal, `U` on and above it; `swaps[i]` is the row
/// swapped with row `i` at step `i`. Returns whether every pivot is non-zero.
#[inline(never)]
pub(super) fn factorize_lu<const N: usize>(lu: &mut [Real], swaps: &mut [usize]) -> bool {
    let (lu, swaps) = (&mut lu[..N * N], &mut swaps[..N]);
    let mut invertible = true;
    for i in 0..N {
        let mut piv = i;
        let mut best = lu[i * N + i].abs();
        for r in i + 1..N {
            let v = lu[i * N + r].abs();
            if v > best {
                best = v;
                piv = r;
            }
        }
        swaps[i] = piv;
        if best == 0.0 {
            // No non-zero entry on this column: singular.
            invertible = false;
            continue;
        }
        if piv != i {
            for c in 0..N {
                lu.swap(c * N + i, c * N + piv);
            }
        }
        let inv_diag = 1.0 / lu[i * N + i];
        for r in i + 1..N {
            lu[i * N + r] *= inv_diag;
        }
        for c in i + 1..N {
            let u = lu[c * N + i];
            if u != 0.0 {
                for r in i + 1..N {
                    lu[c * N + r] -= lu[i * N + r] * u;
                }
            }
        }
    }
    invertible
}

/// `x ← A⁻¹·x` with the factors and row swaps of [`factorize_lu`].
#[inline(never)]
pub(super) fn solve_lu<const N: usize>(lu: &[Real], swaps: &[usize], x: &mut [Real]) {
    let (lu, swaps, x) = (&lu[..N * N], &swaps[..N], &mut x[..N]);
    for i in 0..N {
        let piv = swaps[i];
        if piv != i {
            x.swap(i, piv);
        }
    }
    // Forward substitution with the unit lower triangle, column by column.
    for j in 0..N {
        let xj = x[j];
        if xj != 0.0 {
            for i in j + 1..N {
                x[i] -= lu[j * N + i] * xj;
            }
        }
    }
    // Back substitution with the upper triangle, column by column.
    for j in (0..N).rev() {
        let xj = x[j] / lu[j * N + j];
        x[j] = xj;
        if xj != 0.0 {
            for i in 0..j {
                x[i] -= lu[j * N + i] * xj;
            }
        }
    }
}
