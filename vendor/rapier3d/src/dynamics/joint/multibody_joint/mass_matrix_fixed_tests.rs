//! Tests of gymfleet patch 34 (see `PATCHES.md`): the fixed-size kernels of
//! `mass_matrix_fixed.rs` against the generic loops of `mass_matrix_lu.rs`, bit for bit.

use super::mass_matrix_fixed::{MAX_FIXED_DIM, with_fixed_dim};
use super::mass_matrix_lu::{
    factorize_lu_generic, factorize_symmetric_generic, solve_lu_generic, solve_symmetric_generic,
};
use crate::alloc_prelude::*;
use crate::math::Real;

/// Deterministic values in `[-0.5, 0.5)`.
fn values(n: usize, seed: usize) -> Vec<Real> {
    (0..n)
        .map(|i| ((i * 37 + seed * 101 + (i * i) % 13) % 41) as Real / 41.0 - 0.5)
        .collect()
}

fn bits(v: &[Real]) -> Vec<u64> {
    v.iter().map(|x| f64::from(*x).to_bits()).collect()
}

/// Every kernel gives the generic loops' bits, for every dimension it covers: the
/// factors, the pivots, the solutions, and a pivot that stops the symmetric one.
#[test]
fn the_fixed_kernels_give_the_generic_bits() {
    assert!(with_fixed_dim!(0usize, solve_symmetric(&[], &mut [])).is_none());
    let past = MAX_FIXED_DIM + 1;
    assert!(with_fixed_dim!(past, factorize_symmetric(&mut [])).is_none());
    for n in 1..=MAX_FIXED_DIM {
        // Symmetric positive definite, `BᵀB + I`, as a mass matrix is.
        let b = values(n * n, n);
        let mut spd = vec![0.0; n * n];
        for c in 0..n {
            for r in 0..n {
                let dot: Real = (0..n).map(|k| b[r * n + k] * b[c * n + k]).sum();
                spd[c * n + r] = dot + if r == c { 1.0 } else { 0.0 };
            }
        }
        let (mut generic, mut fixed) = (spd.clone(), spd.clone());
        assert!(factorize_symmetric_generic(&mut generic, n));
        assert_eq!(
            with_fixed_dim!(n, factorize_symmetric(&mut fixed)),
            Some(true)
        );
        assert_eq!(bits(&generic), bits(&fixed), "n = {n}: L·D·Lᵀ");
        let rhs = values(n, n + 7);
        let (mut x_generic, mut x_fixed) = (rhs.clone(), rhs.clone());
        solve_symmetric_generic(&generic, &mut x_generic);
        assert!(with_fixed_dim!(n, solve_symmetric(&fixed, &mut x_fixed)).is_some());
        assert_eq!(bits(&x_generic), bits(&x_fixed), "n = {n}: L·D·Lᵀ solve");

        // Not positive definite: both stop at the same pivot.
        let mut indefinite = spd.clone();
        indefinite[(n - 1) * n + n - 1] = -1.0;
        let (mut generic, mut fixed) = (indefinite.clone(), indefinite);
        assert!(!factorize_symmetric_generic(&mut generic, n));
        assert_eq!(
            with_fixed_dim!(n, factorize_symmetric(&mut fixed)),
            Some(false)
        );
        assert_eq!(bits(&generic), bits(&fixed), "n = {n}: stopped L·D·Lᵀ");

        // General, dominant off the diagonal so that most steps swap rows, and with a
        // zero column past the first dimension (singular).
        let mut general = values(n * n, 3 * n);
        for i in 0..n {
            general[((i + 1) % n) * n + i] += 3.0;
        }
        if n > 2 {
            general[n..2 * n].fill(0.0);
        }
        let (mut generic, mut fixed) = (general.clone(), general);
        let (mut swaps_generic, mut swaps_fixed) = (vec![0; n], vec![0; n]);
        let invertible = factorize_lu_generic(&mut generic, n, &mut swaps_generic);
        assert_eq!(invertible, n <= 2, "n = {n}");
        assert_eq!(
            with_fixed_dim!(n, factorize_lu(&mut fixed, &mut swaps_fixed)),
            Some(invertible)
        );
        assert_eq!(swaps_generic, swaps_fixed, "n = {n}: pivots");
        assert_eq!(bits(&generic), bits(&fixed), "n = {n}: LU");
        let (mut x_generic, mut x_fixed) = (rhs.clone(), rhs);
        solve_lu_generic(&generic, &swaps_generic, &mut x_generic);
        assert!(with_fixed_dim!(n, solve_lu(&fixed, &swaps_fixed, &mut x_fixed)).is_some());
        assert_eq!(bits(&x_generic), bits(&x_fixed), "n = {n}: LU solve");
    }
}
