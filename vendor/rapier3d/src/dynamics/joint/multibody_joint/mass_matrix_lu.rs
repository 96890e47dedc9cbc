//! An LU factorisation of a multibody's (small, dense) mass matrix in reusable storage.
//!
//! gymfleet patch (see `PATCHES.md`): the multibody mass matrices are refactorised at every
//! substep. nalgebra's `LU::new` takes an owned matrix and allocates its permutation, so each
//! factorisation cost two allocations (plus the `into_owned` copy of the matrix view) and ran
//! nalgebra's generic view code on matrices of a few rows. This type factorises in place into
//! storage it keeps, with the same algorithm (Doolittle with partial row pivoting).

use crate::alloc_prelude::*;
use crate::math::{DMatrix, Real};
use na::{Dim, Dyn, Matrix, Storage, StorageMut};

/// LU factorisation with partial (row) pivoting of a square matrix, `P·A = L·U`, kept in
/// storage that is reused by the next factorisation of the same dimension.
#[cfg_attr(feature = "serde-serialize", derive(Serialize, Deserialize))]
#[derive(Clone, Debug)]
pub struct MassMatrixLu {
    /// `L` (unit diagonal, not stored) below the diagonal, `U` on and above it.
    lu: DMatrix,
    /// Row `i` was swapped with row `swaps[i] >= i` at step `i`.
    swaps: Vec<usize>,
    /// Whether every pivot is non-zero.
    invertible: bool,
}

impl Default for MassMatrixLu {
    fn default() -> Self {
        Self {
            lu: DMatrix::zeros(0, 0),
            swaps: Vec::new(),
            invertible: true,
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

    fn factorize_in_place(&mut self) {
        let n = self.lu.nrows();
        self.swaps.clear();
        self.invertible = true;
        // Column-major: column `c` is `lu[c * n..(c + 1) * n]`.
        let lu = self.lu.as_mut_slice();

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
            self.swaps.push(piv);
            if best == 0.0 {
                // No non-zero entry on this column: singular.
                self.invertible = false;
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
        let lu = self.lu.as_slice();
        for k in 0..b.ncols() {
            let mut x = b.column_mut(k);
            for (i, &piv) in self.swaps.iter().enumerate() {
                if piv != i {
                    x.swap_rows(i, piv);
                }
            }
            // Forward substitution with the unit lower triangle, column by column.
            for j in 0..n {
                let xj = x[j];
                if xj != 0.0 {
                    for (i, l) in lu[j * n..(j + 1) * n].iter().enumerate().skip(j + 1) {
                        x[i] -= l * xj;
                    }
                }
            }
            // Back substitution with the upper triangle, column by column.
            for j in (0..n).rev() {
                let col = &lu[j * n..(j + 1) * n];
                let xj = x[j] / col[j];
                x[j] = xj;
                if xj != 0.0 {
                    for (i, u) in col.iter().enumerate().take(j) {
                        x[i] -= u * xj;
                    }
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::MassMatrixLu;
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

    #[test]
    fn reports_a_singular_matrix() {
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 4.0]);
        let mut lu = MassMatrixLu::default();
        lu.factorize(&a);
        assert!(!lu.is_invertible());
        assert!(!lu.solve_mut(&mut DVector::from_row_slice(&[1.0, 1.0])));
    }
}
