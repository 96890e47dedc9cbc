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
        // gymfleet patch 28 (see `PATCHES.md`): each column is solved in a contiguous buffer
        // (on the stack for a multibody of up to `STACK_DOFS` DoFs), not through the
        // column's strided view, with the same operations in the same order.
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
        for (i, &piv) in self.swaps.iter().enumerate() {
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
