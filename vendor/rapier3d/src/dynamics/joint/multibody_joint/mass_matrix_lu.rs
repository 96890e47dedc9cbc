//! An LU factorisation of a multibody's (small, dense) mass matrix in reusable storage.
//!
//! gymfleet patch (see `PATCHES.md`): the multibody mass matrices are refactorised at every
//! substep. nalgebra's `LU::new` takes an owned matrix and allocates its permutation, so each
//! factorisation cost two allocations (plus the `into_owned` copy of the matrix view) and ran
//! nalgebra's generic view code on matrices of a few rows. This type factorises in place into
//! storage it keeps, with the same algorithm (Doolittle with partial row pivoting). A matrix
//! known to be symmetric positive definite (the plain mass matrix) can be factorized as
//! `L·D·Lᵀ` instead (gymfleet patch 29).

use super::mass_matrix_fixed::with_fixed_dim;
use crate::alloc_prelude::*;
use crate::math::{DMatrix, Real};
use na::{Dim, Dyn, Matrix, Storage, StorageMut};

/// LU factorisation with partial (row) pivoting of a square matrix, `P·A = L·U`, or, for a
/// symmetric positive definite one, `A = L·D·Lᵀ` ([`MassMatrixLu::factorize_symmetric_leading`]),
/// kept in storage that is reused by the next factorisation of the same dimension.
#[cfg_attr(feature = "serde-serialize", derive(Serialize, Deserialize))]
#[derive(Clone, Debug)]
pub struct MassMatrixLu {
    /// `L` (unit diagonal, not stored) below the diagonal, `U` on and above it; for
    /// `L·D·Lᵀ`, see `symmetric`.
    lu: DMatrix,
    /// Row `i` was swapped with row `swaps[i] >= i` at step `i`.
    swaps: Vec<usize>,
    /// Whether every pivot is non-zero.
    invertible: bool,
    /// Whether `lu` holds `L·D·Lᵀ` (gymfleet patch 29): row `j` of `L` (unit diagonal, not
    /// stored) above the diagonal of column `j`, `D` on the diagonal, nothing below it read,
    /// and no row swaps.
    symmetric: bool,
}

impl Default for MassMatrixLu {
    fn default() -> Self {
        Self {
            lu: DMatrix::zeros(0, 0),
            swaps: Vec::new(),
            invertible: true,
            symmetric: false,
        }
    }
}

impl MassMatrixLu {
    /// The dimension of the factorised matrix.
    pub fn dim(&self) -> usize {
        self.lu.nrows()
    }

    /// Whether the factorised matrix is invertible.
    pub fn is_invertible(&self) -> bool {
        self.invertible
    }

    /// The factors' storage (gymfleet patch 37, see `PATCHES.md`: for
    /// [`super::Multibody::workspace_buffers`]).
    pub(super) fn storage(&self) -> &[Real] {
        self.lu.as_slice()
    }

    /// Makes this factorisation a copy of `other`, reusing this one's storage (gymfleet patch,
    /// see `PATCHES.md`).
    pub fn copy_from(&mut self, other: &MassMatrixLu) {
        if self.lu.shape() != other.lu.shape() {
            self.lu = other.lu.clone();
        } else {
            self.lu.copy_from(&other.lu);
        }
        self.swaps.clear();
        self.swaps.extend_from_slice(&other.swaps);
        self.invertible = other.invertible;
        self.symmetric = other.symmetric;
    }

    /// Factorises the square matrix `a`, reusing this factorisation's storage.
    pub fn factorize<S: Storage<Real, Dyn, Dyn>>(&mut self, a: &Matrix<Real, Dyn, Dyn, S>) {
        let n = a.nrows();
        assert_eq!(n, a.ncols(), "LU: the matrix must be square");
        if self.lu.nrows() != n {
            self.lu = DMatrix::zeros(n, n);
        }
        self.lu.copy_from(a);
        self.factorize_in_place();
    }

    /// Factorises the leading `n × n` block of the column-major matrix `a` (the mass matrix
    /// without its kinematic DoFs), reusing this factorisation's storage.
    pub fn factorize_leading(&mut self, a: &DMatrix, n: usize) {
        if self.lu.nrows() != n {
            self.lu = DMatrix::zeros(n, n);
        }
        let rows = a.nrows();
        let (src, dst) = (a.as_slice(), self.lu.as_mut_slice());
        for c in 0..n {
            dst[c * n..(c + 1) * n].copy_from_slice(&src[c * rows..c * rows + n]);
        }
        self.factorize_in_place();
    }

    /// Factorizes the leading `n × n` block of the column-major matrix `a`, known to be
    /// symmetric (only its upper triangle is read, unless it falls back), as `L·D·Lᵀ`
    /// (gymfleet patch 29): half the multiply-adds of the LU factorization, no pivot search,
    /// and every product a contiguous dot product (row `j` of `L` is kept in column `j`,
    /// above the diagonal, and computed from the rows above it). A mass matrix is symmetric positive definite, where
    /// this needs no pivoting; if a pivot comes out not positive (or not finite), the block
    /// is factorized by [`Self::factorize_leading`] instead, which reads all of it.
    pub fn factorize_symmetric_leading(&mut self, a: &DMatrix, n: usize) {
        if self.lu.nrows() != n {
            self.lu = DMatrix::zeros(n, n);
        }
        let rows = a.nrows();
        let (src, dst) = (a.as_slice(), self.lu.as_mut_slice());
        for c in 0..n {
            dst[c * n..c * n + c + 1].copy_from_slice(&src[c * rows..c * rows + c + 1]);
        }
        self.swaps.clear();
        self.invertible = true;
        self.symmetric = true;
        let lu = self.lu.as_mut_slice();
        // gymfleet patch 34: the same loops for a constant dimension (`mass_matrix_fixed.rs`).
        let factorized = match with_fixed_dim!(n, factorize_symmetric(lu)) {
            Some(factorized) => factorized,
            None => factorize_symmetric_generic(lu, n),
        };
        if !factorized {
            self.factorize_leading(a, n);
        }
    }

    fn factorize_in_place(&mut self) {
        let n = self.lu.nrows();
        self.swaps.clear();
        self.invertible = true;
        self.symmetric = false;
        // Column-major: column `c` is `lu[c * n..(c + 1) * n]`.
        let lu = self.lu.as_mut_slice();
        self.swaps.resize(n, 0);
        // gymfleet patch 34: the same loops for a constant dimension (`mass_matrix_fixed.rs`).
        self.invertible = match with_fixed_dim!(n, factorize_lu(lu, &mut self.swaps)) {
            Some(invertible) => invertible,
            None => factorize_lu_generic(lu, n, &mut self.swaps),
        };
    }

    /// Solves `A·x = b` in place for every column of `b`. Returns `false` (and leaves garbage in
    /// `b`) if the matrix is not invertible.
    pub fn solve_mut<R: Dim, C: Dim, S: StorageMut<Real, R, C>>(
        &self,
        b: &mut Matrix<Real, R, C, S>,
    ) -> bool {
        let n = self.dim();
        assert_eq!(n, b.nrows(), "LU solve matrix dimension mismatch.");
        if !self.invertible {
            return false;
        }
        if n == 0 {
            return true;
        }
        if b.strides().0 == 1 {
            // gymfleet patch 34 (see `PATCHES.md`): columns with unit row stride (a vector, or
            // the columns of a column-major matrix or of its views) are solved in place,
            // without the copies through nalgebra's strided iterators.
            for k in 0..b.ncols() {
                let mut column = b.column_mut(k);
                // SAFETY: the column's `n` entries are contiguous from its first one (unit
                // row stride), and `column` borrows them mutably for this block.
                let x = unsafe { core::slice::from_raw_parts_mut(column.as_mut_ptr(), n) };
                self.solve_column(x);
            }
            return true;
        }
        // gymfleet patch 28 (see `PATCHES.md`): otherwise each column is solved in a
        // contiguous buffer (on the stack for a multibody of up to `STACK_DOFS` DoFs), not
        // through the column's strided view, with the same operations in the same order.
        const STACK_DOFS: usize = 64;
        let mut stack = [0.0; STACK_DOFS];
        let mut heap = Vec::new();
        let x = if n <= STACK_DOFS {
            &mut stack[..n]
        } else {
            heap.resize(n, 0.0);
            &mut heap[..]
        };
        for k in 0..b.ncols() {
            let mut column = b.column_mut(k);
            for (xi, bi) in x.iter_mut().zip(column.iter()) {
                *xi = *bi;
            }
            self.solve_column(x);
            for (bi, xi) in column.iter_mut().zip(x.iter()) {
                *bi = *xi;
            }
        }
        true
    }

    /// `x ← A⁻¹·x` for one contiguous column.
    fn solve_column(&self, x: &mut [Real]) {
        let n = x.len();
        let lu = self.lu.as_slice();
        // gymfleet patch 34: the same loops for a constant dimension (`mass_matrix_fixed.rs`).
        if self.symmetric {
            if with_fixed_dim!(n, solve_symmetric(lu, x)).is_none() {
                solve_symmetric_generic(lu, x);
            }
        } else if with_fixed_dim!(n, solve_lu(lu, &self.swaps, x)).is_none() {
            solve_lu_generic(lu, &self.swaps, x);
        }
    }
}

/// `L·D·Lᵀ` of the column-major `n × n` matrix in `lu` (its upper triangle), in place: row
/// `j` of `L` (unit diagonal, not stored) above the diagonal of column `j`, `D` on the
/// diagonal; every product a contiguous dot product (row `j` of `L` is computed from the rows
/// above it). False, with `lu` partly overwritten, if a pivot is not positive (or not
/// finite). `mass_matrix_fixed::factorize_symmetric` is the same for a constant `n`.
pub(super) fn factorize_symmetric_generic(lu: &mut [Real], n: usize) -> bool {
    for j in 0..n {
        let (done, rest) = lu.split_at_mut(j * n);
        let col_j = &mut rest[..j + 1];
        // `y_k = A[k, j] − Σ_{m<k} L[k, m]·y_m`, in place of `A[k, j]`.
        for k in 0..j {
            let row_k = &done[k * n..k * n + k];
            let (ys, y_k) = col_j.split_at_mut(k);
            let mut y = y_k[0];
            for (l, ym) in row_k.iter().zip(ys.iter()) {
                y -= l * ym;
            }
            y_k[0] = y;
        }
        // `L[j, k] = y_k / d_k` and `d_j = A[j, j] − Σ_k y_k·L[j, k]`.
        let mut d = col_j[j];
        for (k, y) in col_j[..j].iter_mut().enumerate() {
            let l = *y / done[k * n + k];
            d -= *y * l;
            *y = l;
        }
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        col_j[j] = d;
    }
    true
}

/// Doolittle LU with partial row pivoting of the column-major `n × n` matrix in `lu`, in
/// place: `L` (unit diagonal) below the diagonal, `U` on and above it; `swaps[i]` (of `n`)
/// becomes the row swapped with row `i` at step `i`. Returns whether every pivot is non-zero.
/// `mass_matrix_fixed::factorize_lu` is the same for a constant `n`.
pub(super) fn factorize_lu_generic(lu: &mut [Real], n: usize, swaps: &mut [usize]) -> bool {
    let mut invertible = true;
    for i in 0..n {
        let col_i = &lu[i * n..(i + 1) * n];
        let mut piv = i;
        let mut best = col_i[i].abs();
        for (r, v) in col_i.iter().enumerate().skip(i + 1) {
            if v.abs() > best {
                best = v.abs();
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
            for c in 0..n {
                lu.swap(c * n + i, c * n + piv);
            }
        }
        let (left, right) = lu.split_at_mut((i + 1) * n);
        let col_i = &mut left[i * n..];
        let inv_diag = 1.0 / col_i[i];
        for l in &mut col_i[i + 1..] {
            *l *= inv_diag;
        }
        for col_c in right.chunks_exact_mut(n) {
            let u = col_c[i];
            if u != 0.0 {
                for (x, l) in col_c[i + 1..].iter_mut().zip(&col_i[i + 1..]) {
                    *x -= l * u;
                }
            }
        }
    }
    invertible
}

/// `x ← A⁻¹·x` with the factors of [`factorize_symmetric_generic`]: forward with `L`, scaled
/// by `D⁻¹`, back with `Lᵀ`.
pub(super) fn solve_symmetric_generic(lu: &[Real], x: &mut [Real]) {
    let n = x.len();
    for j in 0..n {
        let row_j = &lu[j * n..j * n + j];
        let (before, x_j) = x.split_at_mut(j);
        let mut y = x_j[0];
        for (l, xk) in row_j.iter().zip(before.iter()) {
            y -= l * xk;
        }
        x_j[0] = y;
    }
    for (j, xj) in x.iter_mut().enumerate() {
        *xj /= lu[j * n + j];
    }
    for i in (0..n).rev() {
        let (before, x_i) = x.split_at_mut(i);
        let xi = x_i[0];
        if xi != 0.0 {
            for (xk, l) in before.iter_mut().zip(&lu[i * n..i * n + i]) {
                *xk -= l * xi;
            }
        }
    }
}

/// `x ← A⁻¹·x` with the factors and row swaps of [`factorize_lu_generic`].
pub(super) fn solve_lu_generic(lu: &[Real], swaps: &[usize], x: &mut [Real]) {
    let n = x.len();
    for (i, &piv) in swaps.iter().enumerate() {
        if piv != i {
            x.swap(i, piv);
        }
    }
    // Forward substitution with the unit lower triangle, column by column.
    for j in 0..n {
        let xj = x[j];
        if xj != 0.0 {
            let below = &lu[j * n + j + 1..(j + 1) * n];
            for (xi, l) in x[j + 1..].iter_mut().zip(below) {
                *xi -= l * xj;
            }
        }
    }
    // Back substitution with the upper triangle, column by column.
    for j in (0..n).rev() {
        let col = &lu[j * n..(j + 1) * n];
        let xj = x[j] / col[j];
        x[j] = xj;
        if xj != 0.0 {
            for (xi, u) in x[..j].iter_mut().zip(&col[..j]) {
                *xi -= u * xj;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::MassMatrixLu;
    use crate::alloc_prelude::*;
    use crate::math::{DMatrix, DVector};

    #[test]
    fn solves_a_system_that_needs_pivoting() {
        let a = DMatrix::from_row_slice(3, 3, &[0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0]);
        let x = DVector::from_row_slice(&[1.0, -2.0, 0.5]);
        let mut b = &a * &x;
        let mut lu = MassMatrixLu::default();
        lu.factorize(&a);
        assert!(lu.solve_mut(&mut b));
        assert!((b - x).amax() < 1.0e-5);
    }

    /// The solve before patch 28: through the column's view, index by index.
    fn solve_by_index(lu: &MassMatrixLu, x: &mut DVector) {
        let n = lu.dim();
        let a = lu.lu.as_slice();
        for (i, &piv) in lu.swaps.iter().enumerate() {
            if piv != i {
                x.swap_rows(i, piv);
            }
        }
        for j in 0..n {
            let xj = x[j];
            if xj != 0.0 {
                for i in j + 1..n {
                    x[i] -= a[j * n + i] * xj;
                }
            }
        }
        for j in (0..n).rev() {
            let xj = x[j] / a[j * n + j];
            x[j] = xj;
            if xj != 0.0 {
                for i in 0..j {
                    x[i] -= a[j * n + i] * xj;
                }
            }
        }
    }

    /// gymfleet patch 28: the columns of a strided view, solved in a contiguous buffer, get
    /// the bits the index-by-index solve gives, for a multibody-sized matrix and one past the
    /// stack buffer.
    #[test]
    fn a_view_solves_to_the_bits_of_the_index_by_index_solve() {
        for n in [9, 70] {
            // Dominant off the diagonal (at column `i + 1` of row `i`): every step pivots.
            let a = DMatrix::from_fn(n, n, |i, j| {
                let x = ((i * 31 + j * 17) % 23) as f32 / 23.0 - 0.5;
                if j == (i + 1) % n {
                    x + 3.0 * (1 + (i % 3)) as f32
                } else {
                    x
                }
            });
            let mut lu = MassMatrixLu::default();
            lu.factorize(&a);
            let swaps = lu.swaps.iter().enumerate().filter(|(i, p)| i != *p).count();
            assert!(swaps > n / 2, "n = {n}: {swaps} row swaps");
            let mut big = DMatrix::from_fn(n + 3, 5, |i, j| ((i * 7 + j * 3) % 11) as f32 - 5.0);
            let expected: Vec<DVector> = (1..4)
                .map(|k| {
                    let mut x = DVector::from_iterator(n, big.column(k).rows(2, n).iter().copied());
                    solve_by_index(&lu, &mut x);
                    x
                })
                .collect();
            assert!(lu.solve_mut(&mut big.view_mut((2, 1), (n, 3))));
            for (k, x) in expected.iter().enumerate() {
                assert_eq!(
                    &big.column(k + 1).rows(2, n).into_owned(),
                    x,
                    "n = {n}, column {k}"
                );
            }
            // The rows and columns outside the view are untouched.
            assert_eq!(big[(0, 1)], ((3) % 11) as f32 - 5.0);
            assert_eq!(big[(2, 0)], ((14) % 11) as f32 - 5.0);
            // Every other row (a row stride of 2, solved through the copy, patch 34): the
            // same bits as the contiguous columns, the rows between untouched.
            let mut strided = DMatrix::from_fn(2 * n, 3, |i, j| {
                if i % 2 == 0 {
                    big[(2 + i / 2, 1 + j)]
                } else {
                    7.0
                }
            });
            let mut contiguous = DMatrix::from_fn(n, 3, |i, j| strided[(2 * i, j)]);
            assert!(lu.solve_mut(&mut strided.rows_with_step_mut(0, n, 1)));
            assert!(lu.solve_mut(&mut contiguous));
            for j in 0..3 {
                for i in 0..n {
                    assert_eq!(strided[(2 * i, j)], contiguous[(i, j)], "n = {n}");
                    assert_eq!(strided[(2 * i + 1, j)], 7.0);
                }
            }
        }
    }

    /// A symmetric positive definite `n × n` matrix, `BᵀB + I`, as a mass matrix is.
    fn mass_like(n: usize) -> DMatrix {
        let b = DMatrix::from_fn(n, n, |i, j| ((i * 13 + j * 7) % 17) as f32 / 17.0 - 0.4);
        b.transpose() * &b + DMatrix::identity(n, n)
    }

    /// gymfleet patch 29: `L·D·Lᵀ` of the leading block of a larger matrix (whose other
    /// entries it never reads) solves as the pivoted LU does, without a row swap.
    #[test]
    fn the_symmetric_factorization_solves_as_the_lu_does() {
        for n in [1, 9, 23] {
            let a = mass_like(n);
            let mut padded = DMatrix::from_element(n + 2, n + 2, f32::NAN);
            padded.view_mut((0, 0), (n, n)).copy_from(&a);
            // Below the diagonal is never read either.
            for c in 0..n {
                for r in c + 1..n {
                    padded[(r, c)] = f32::NAN;
                }
            }
            let mut ldl = MassMatrixLu::default();
            ldl.factorize_symmetric_leading(&padded, n);
            assert!(ldl.symmetric && ldl.swaps.is_empty(), "n = {n}: fell back");
            let mut lu = MassMatrixLu::default();
            lu.factorize(&a);
            let b = DMatrix::from_fn(n, 2, |i, j| (i as f32 - 3.0) * (j as f32 + 0.5));
            let (mut x_ldl, mut x_lu) = (b.clone(), b.clone());
            assert!(ldl.solve_mut(&mut x_ldl) && lu.solve_mut(&mut x_lu));
            let scale = x_lu.amax();
            assert!(
                (&x_ldl - &x_lu).amax() <= 1.0e-5 * scale,
                "n = {n}: {x_ldl} vs {x_lu}"
            );
            assert!(
                (&a * &x_ldl - &b).amax() <= 1.0e-4 * b.amax(),
                "n = {n}: residual"
            );
        }
    }

    /// A symmetric matrix that is not positive definite goes to the pivoted LU.
    #[test]
    fn an_indefinite_matrix_falls_back_to_the_lu() {
        for a in [
            DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 1.0, 0.0]),
            DMatrix::from_row_slice(3, 3, &[2.0, 1.0, 0.0, 1.0, -3.0, 1.0, 0.0, 1.0, 1.0]),
        ] {
            let mut ldl = MassMatrixLu::default();
            ldl.factorize_symmetric_leading(&a, a.nrows());
            assert!(!ldl.symmetric, "{a}");
            let x = DVector::from_fn(a.nrows(), |i, _| 1.0 - i as f32);
            let mut b = &a * &x;
            assert!(ldl.solve_mut(&mut b));
            assert!((b - x).amax() < 1.0e-5);
        }
    }

    #[test]
    fn reports_a_singular_matrix() {
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 4.0]);
        let mut lu = MassMatrixLu::default();
        lu.factorize(&a);
        assert!(!lu.is_invertible());
        assert!(!lu.solve_mut(&mut DVector::from_row_slice(&[1.0, 1.0])));
    }
}
