//! gymfleet patch 43: MuJoCo's compliant contacts (`solref`/`solimp`), see `PATCHES.md`.
//!
//! MuJoCo solves a contact row as a regularized constraint: with impedance `d ∈ (0, 1)` the
//! row's acceleration becomes `a = d·a_ref + (1 − d)·a_0`, where `a_0` is the unconstrained
//! acceleration along the row and `a_ref = −B·v − K·d·r` pulls the penetration `r` back
//! like a damped spring. `solref = (timeconst, dampratio)` gives that spring its time
//! constant and damping ratio (`K = 1/(dmax²·timeconst²·dampratio²)`, `B = 2/(dmax·timeconst)`),
//! or the stiffness and damping directly when negative (`K = −solref₀/dmax²`,
//! `B = −solref₁/dmax`); `solimp = (dmin, dmax, width, midpoint, power)` makes `d` grow
//! from `dmin` at the surface to `dmax` at `width` deep, along a sigmoid.
//!
//! The projected Gauss-Seidel update of such a row is exactly Rapier's soft-constraint
//! update `λ ← cfm·(λ − m·(J·v + rhs))` with `cfm = d` and `rhs = −(v₀ + h·a_ref)`, `v₀`
//! the row's velocity at the start of the substep (before the substep's forces): the
//! solver solves it in both its passes. A collider opts in with
//! [`ColliderMaterial::compliance`](crate::geometry::ColliderMaterial); a pair gets
//! [`PairCompliance::mix`] of its two colliders' (MuJoCo's `mj_contactParam`).

use crate::math::Real;

/// MuJoCo's default `solref`: a 0.02 s time constant, critically damped.
pub const DEFAULT_SOLREF: [Real; 2] = [0.02, 1.0];
/// MuJoCo's default `solimp`.
pub const DEFAULT_SOLIMP: [Real; 5] = [0.9, 0.95, 0.001, 0.5, 2.0];
/// MuJoCo's `mjMINVAL`.
const MIN_VAL: Real = 1.0e-15;
/// MuJoCo's `mjMINMU`, the least friction coefficient.
const MIN_MU: Real = 1.0e-5;

/// One collider's contact compliance, as a MuJoCo geom gives it.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Serialize, serde::Deserialize))]
pub struct ContactCompliance {
    /// `(timeconst, dampratio)`, or `(−stiffness, −damping)`.
    pub solref: [Real; 2],
    /// `(dmin, dmax, width, midpoint, power)`.
    pub solimp: [Real; 5],
    /// The weight of this collider's `solref`/`solimp` when mixed with another's of the same
    /// priority.
    pub solmix: Real,
    /// Of two colliders, the one of higher priority gives the pair its parameters.
    pub priority: i32,
    /// Distance (m) below which the contact acts: a pair's is the sum of its two colliders'
    /// (MuJoCo's `getMargin`), its spring's rest point.
    pub margin: Real,
    /// Distance beyond the margin in which the contact is detected but pushes nothing (a
    /// pair's is the sum of its two colliders').
    pub gap: Real,
    /// MuJoCo's friction cone (`<option cone>`): its pyramid makes the normal direction
    /// stiffer as friction falls (see [`PairCompliance::with_friction`]).
    pub pyramidal: bool,
    /// MuJoCo's `impratio`, the friction-to-normal impedance ratio.
    pub impratio: Real,
    /// The collider's body's translational inverse weight, MuJoCo's `body_invweight0[0]`
    /// (the mean of `J·M⁻¹·Jᵀ`'s translational diagonal at the body's centre of mass, at
    /// the model's initial pose; 0 for a fixed body): MuJoCo sizes a contact's regulariser
    /// `R = (1 − d)/d·A` from this approximation of `A`, not from the row's own. Zero on
    /// both colliders: the row's exact `A`.
    pub invweight: Real,
    /// gymfleet patch 47: MuJoCo's `condim`: 1 frictionless, 3 sliding friction (the
    /// default), 4 with torsional friction, 6 with rolling friction too. A pair takes the
    /// higher priority's, else the larger.
    pub condim: u8,
    /// gymfleet patch 47: the torsional friction coefficient (m: the torque about the
    /// normal is at most `torsional·λₙ`), MuJoCo's `friction[1]` (default 0.005). A pair
    /// takes the higher priority's, else the larger.
    pub torsional: Real,
    /// gymfleet patch 47: the rolling friction coefficient (m), MuJoCo's `friction[2]`
    /// (default 0.0001), mixed as `torsional`.
    pub rolling: Real,
    /// gymfleet patch 51: solve a pyramidal contact of `condim` 3 as MuJoCo's four facet
    /// rows (default `false`: a normal row and two friction rows in the pyramid's section).
    /// A pair's are its facets when either collider's are.
    pub facets: bool,
}

impl Default for ContactCompliance {
    fn default() -> Self {
        Self {
            solref: DEFAULT_SOLREF,
            solimp: DEFAULT_SOLIMP,
            solmix: 1.0,
            priority: 0,
            margin: 0.0,
            gap: 0.0,
            pyramidal: true,
            impratio: 1.0,
            invweight: 0.0,
            condim: 3,
            torsional: 0.005,
            rolling: 0.0001,
            facets: false,
        }
    }
}

/// A contact pair's compliance, ready for the solver: the spring and damper of MuJoCo's
/// reference acceleration, and the impedance curve.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Serialize, serde::Deserialize))]
pub struct PairCompliance {
    /// `K` of `a_ref = −B·v − K·d·(dist − rest)`.
    pub stiffness: Real,
    /// `B`.
    pub damping: Real,
    /// The `solref` `K` and `B` come from: in the standard form, MuJoCo's rule `timeconst ≥
    /// 2·dt` (`refsafe`) is applied at each step's `dt` (see [`Self::gains`]).
    pub solref: [Real; 2],
    /// `(dmin, dmax, width, midpoint, power)`.
    pub solimp: [Real; 5],
    /// The distance below which the contact is detected: the margins and gaps summed.
    pub margin: Real,
    /// The distance below which it acts, its spring's rest point: the margins summed
    /// (MuJoCo's `includemargin`; a contact at or beyond it is excluded).
    pub rest: Real,
    /// The regulariser's scale in the normal direction: 1 for an elliptic cone; for a
    /// pyramid, `μ²·(1 + μ²)/2` (see [`Self::with_friction`]).
    pub normal_scale: Real,
    /// Whether [`Self::with_friction`] scales the normal regulariser (a pyramidal cone).
    pub pyramidal: bool,
    /// `impratio` (see [`ContactCompliance::impratio`]).
    pub impratio: Real,
    /// The two colliders' [`ContactCompliance::invweight`] summed (MuJoCo's `tran`), or 0
    /// for the row's exact `A`.
    pub invweight: Real,
    /// The pair's friction coefficient (set by [`Self::with_friction`]; 0 at `condim` 1).
    pub friction: Real,
    /// gymfleet patch 47: the pair's `condim` (see [`ContactCompliance::condim`]).
    pub condim: u8,
    /// gymfleet patch 47: the pair's torsional friction coefficient (m).
    pub torsional: Real,
    /// gymfleet patch 47: the pair's rolling friction coefficient (m).
    pub rolling: Real,
    /// gymfleet patch 51: solved by its pyramid's facets (see [`ContactCompliance::facets`]).
    pub facets: bool,
}

impl PairCompliance {
    /// The compliance of a pair of colliders, either of which may be rigid (`None`): a pair
    /// with one compliant collider takes its parameters.
    pub fn of(a: Option<&ContactCompliance>, b: Option<&ContactCompliance>) -> Option<Self> {
        match (a, b) {
            (None, None) => None,
            (Some(c), None) | (None, Some(c)) => {
                // A rigid side has no parameters of its own, nor an inverse weight.
                let rigid = ContactCompliance {
                    invweight: 0.0,
                    margin: 0.0,
                    gap: 0.0,
                    ..*c
                };
                Some(Self::mix(c, &rigid))
            }
            (Some(a), Some(b)) => Some(Self::mix(a, b)),
        }
    }

    /// MuJoCo's mixing of two geoms' parameters (`mj_contactParam`): the higher priority's,
    /// else `solmix`-weighted means (the smaller of each when a `solref` is in the direct,
    /// negative form); margins and gaps are summed (`getMargin`, `getGap`).
    pub fn mix(a: &ContactCompliance, b: &ContactCompliance) -> Self {
        // gymfleet patch 47: `condim` and the torsional and rolling coefficients are the
        // higher priority's, else the larger of each (`mj_contactParam`).
        let (condim, torsional, rolling) = if a.priority != b.priority {
            let c = if a.priority > b.priority { a } else { b };
            (c.condim, c.torsional, c.rolling)
        } else {
            (
                a.condim.max(b.condim),
                a.torsional.max(b.torsional),
                a.rolling.max(b.rolling),
            )
        };
        let (solref, solimp) = if a.priority != b.priority {
            let c = if a.priority > b.priority { a } else { b };
            (c.solref, c.solimp)
        } else {
            let mix = match (a.solmix >= MIN_VAL, b.solmix >= MIN_VAL) {
                (true, true) => a.solmix / (a.solmix + b.solmix),
                (false, false) => 0.5,
                (false, true) => 0.0,
                (true, false) => 1.0,
            };
            let solref = if a.solref[0] > 0.0 && b.solref[0] > 0.0 {
                core::array::from_fn(|i| mix * a.solref[i] + (1.0 - mix) * b.solref[i])
            } else {
                core::array::from_fn(|i| a.solref[i].min(b.solref[i]))
            };
            let solimp = core::array::from_fn(|i| mix * a.solimp[i] + (1.0 - mix) * b.solimp[i]);
            (solref, solimp)
        };
        let margin = a.margin + b.margin;
        let gap = a.gap + b.gap;
        Self {
            pyramidal: a.pyramidal || b.pyramidal,
            impratio: a.impratio.max(b.impratio),
            invweight: a.invweight + b.invweight,
            condim,
            torsional,
            rolling,
            facets: a.facets || b.facets,
            ..Self::new(solref, solimp, margin + gap, margin)
        }
    }

    /// The pair at friction coefficient `friction`. MuJoCo's pyramidal cone solves a contact
    /// as `2·(condim − 1)` facet rows `J_n ± μ·J_t`, each regularised by
    /// `R_py = 2·μ²·R` with `R = (1 − d)/d·A` from the facet's `A ≈ (1 + μ²)·A_n` and
    /// `μ = friction/√impratio` (`mj_makeImpedance`); their sum along the normal is a single
    /// row regularised by `R_py/4 = μ²·(1 + μ²)/2 · (1 − d)/d · A_n` (condim 3). So a
    /// pyramid's contact is as soft as the file says at `μ = 1`, ten times stiffer at 0.4, and
    /// rigid without friction. An elliptic cone's normal row has `R` itself.
    ///
    /// gymfleet patch 47: with `condim` 4 and 6 the pyramid has 6 and 10 facets, so the
    /// normal row is regularised by `R_py/(2·(condim − 1))`; at `condim` 1 the contact is
    /// frictionless (MuJoCo's `mjCNSTR_CONTACT_FRICTIONLESS`: `R` itself, no friction).
    pub fn with_friction(mut self, friction: Real) -> Self {
        if self.condim == 1 {
            self.friction = 0.0;
            self.normal_scale = 1.0;
            return self;
        }
        self.friction = friction;
        if self.pyramidal {
            let mu2 = (friction.max(MIN_MU) * friction.max(MIN_MU)) / self.impratio.max(MIN_VAL);
            let facet_pairs = if self.condim >= 4 {
                Real::from(self.condim - 1)
            } else {
                2.0
            };
            self.normal_scale = mu2 * (1.0 + mu2) / facet_pairs;
        }
        self
    }

    /// gymfleet patch 47: the coefficients of the pair's angular friction rows: none below
    /// `condim` 4, the torsional row at 4, and the two rolling rows after it at 6.
    pub fn angular_friction(&self) -> &'static [usize] {
        match self.condim {
            4 => &[0],
            6 => &[0, 1, 1],
            _ => &[],
        }
    }

    /// gymfleet patch 47: the coefficient of angular row kind `kind` (0 torsional, 1 rolling).
    pub fn angular_coefficient(&self, kind: usize) -> Real {
        if kind == 0 { self.torsional } else { self.rolling }
    }

    /// gymfleet patch 47: an angular friction row (torsional or rolling) of coefficient `mu`,
    /// as [`Self::friction_row`] with its regulariser scaled as MuJoCo's. On the ellipse,
    /// `R_j·μ_j² = R_t·μ²` (`mj_makeImpedance`): the sliding rows' times `(μ/μ_j)²`. On the
    /// pyramid, each direction is a pair of facets `J_n ± μ_j·J_j`, each regularised by
    /// `R_py`: a pair holding both facets acts along `J_j` as a row of `R_py/(2·μ_j²)` (the
    /// sliding rows' `R_t` scaled so), a pair with one facet left (a direction at its cone's
    /// edge) as `R_py/μ_j²`, twice that. An angular row's `μ_j` is hundreds of times the
    /// sliding one's smaller, so its facets sit at that edge: it is given `R_py/μ_j²`.
    pub fn angular_row(&self, dist: Real, v0: Real, dt: Real, mass: Real, mu: Real) -> (Real, Real) {
        let ratio = self.friction.max(MIN_MU) / mu.max(MIN_MU);
        let edge = if self.pyramidal { 2.0 } else { 1.0 };
        self.scaled_friction_row(dist, v0, dt, mass, edge * ratio * ratio)
    }

    /// From `solref` and `solimp` as MuJoCo gives them (`mj_makeImpedance`).
    pub fn new(solref: [Real; 2], solimp: [Real; 5], margin: Real, rest: Real) -> Self {
        let dmax = solimp[1];
        let stiffness = if solref[0] > 0.0 {
            1.0 / (dmax * dmax * solref[0] * solref[0] * solref[1] * solref[1]).max(MIN_VAL)
        } else {
            -solref[0] / (dmax * dmax).max(MIN_VAL)
        };
        let damping = if solref[1] > 0.0 {
            2.0 / (dmax * solref[0]).max(MIN_VAL)
        } else {
            -solref[1] / dmax.max(MIN_VAL)
        };
        Self {
            stiffness,
            damping,
            solref,
            solimp,
            margin,
            rest,
            normal_scale: 1.0,
            pyramidal: false,
            impratio: 1.0,
            invweight: 0.0,
            friction: 1.0,
            condim: 3,
            torsional: 0.0,
            rolling: 0.0,
            facets: false,
        }
    }

    /// The impedance `d` at separation `dist` (MuJoCo's `getimpedance`).
    pub fn impedance(&self, dist: Real) -> Real {
        let [dmin, dmax, width, midpoint, power] = self.solimp;
        let d = if dmin == dmax || width <= MIN_VAL {
            0.5 * (dmin + dmax)
        } else {
            let x = ((dist - self.rest) / width).abs();
            if x >= 1.0 {
                dmax
            } else if x <= 0.0 {
                dmin
            } else {
                let y = if power == 1.0 {
                    x
                } else if power == 2.0 {
                    // MuJoCo's default power, without `powf`.
                    if x <= midpoint {
                        x * x / midpoint
                    } else {
                        1.0 - (1.0 - x) * (1.0 - x) / (1.0 - midpoint)
                    }
                } else if x <= midpoint {
                    x.powf(power) / midpoint.powf(power - 1.0)
                } else {
                    1.0 - (1.0 - x).powf(power) / (1.0 - midpoint).powf(power - 1.0)
                };
                dmin + y * (dmax - dmin)
            }
        };
        // MuJoCo clamps the regulariser `R = (1 − d)/d·A` at `mjMINVAL`; an impedance of 1
        // would be a rigid row and 0 no row at all.
        d.clamp(MIN_VAL, 1.0 - 1.0e-9)
    }

    /// A point's solver row at separation `dist`, normal velocity `v0` (positive when
    /// separating, at the start of the substep), substep `dt` and effective mass `mass`
    /// (`1/A`): `(rhs, cfm)` for `λ ← cfm·(λ − m·(J·v + rhs))`, clamped at zero. A point at
    /// or beyond the rest distance gets a row that pushes nothing, as MuJoCo excludes it.
    pub fn row(&self, dist: Real, v0: Real, dt: Real, mass: Real) -> (Real, Real) {
        if dist >= self.rest {
            return (SEPARATED_RHS, 1.0);
        }
        let d = self.impedance(dist);
        let (stiffness, damping) = self.gains(dt);
        let aref = -damping * v0 - stiffness * d * (dist - self.rest);
        (-(v0 + dt * aref), self.cfm(d, mass))
    }

    /// A point's friction row along one tangent at separation `dist`, tangential velocity
    /// `v0` at the substep's start and effective mass `mass`: `(rhs, cfm)`. MuJoCo's friction
    /// rows pull the sliding velocity to rest with the damper alone (`a_ref = −B·v`: its
    /// elliptic rows have `K = 0`, and the pyramid's facets `J_n ± μ·J_t` leave only `−B·v_t`
    /// in their difference) and are regularised by `R_t = (1 − d)/d·W·(1 + μ²)/impratio` on
    /// the pyramid (a facet's `R` over `2μ²`, `R_py = 2μ²·R` — `mj_makeImpedance`), `R/impratio`
    /// on the ellipse, `W` the inverse weight (else the row's own `A`). So a tangential load
    /// lets the contact creep at `R_t·F/B` as MuJoCo's does. The cone is the circle
    /// `|λ_t| ≤ μ·λ_n` (MuJoCo's elliptic cone; its pyramid is approximated by it).
    pub fn friction_row(&self, dist: Real, v0: Real, dt: Real, mass: Real) -> (Real, Real) {
        self.scaled_friction_row(dist, v0, dt, mass, 1.0)
    }

    /// [`Self::friction_row`] with its regulariser times `scale`.
    fn scaled_friction_row(
        &self,
        dist: Real,
        v0: Real,
        dt: Real,
        mass: Real,
        scale: Real,
    ) -> (Real, Real) {
        if dist >= self.rest {
            return (0.0, 1.0);
        }
        let d = self.impedance(dist);
        let weight = if self.invweight > 0.0 {
            self.invweight
        } else if mass > 0.0 {
            1.0 / mass
        } else {
            return (0.0, 1.0);
        };
        let facet = if self.pyramidal {
            1.0 + self.friction * self.friction
        } else {
            1.0
        };
        let regulariser = (1.0 - d) / d * weight * facet / self.impratio.max(MIN_VAL) * scale;
        let aref = -self.gains(dt).1 * v0;
        (-(v0 + dt * aref), 1.0 / (1.0 + regulariser * mass))
    }

    /// gymfleet patch 51: a pyramid facet's row at the contact's separation `dist`, its
    /// velocity `v0` at the substep's start (`J_f·v`, positive when separating) and step
    /// `dt`: `(rhs, R_py)` for `λ ← max(0, λ − (J_f·v + rhs + R_py·λ)/(A_f + R_py))`, or `None`
    /// at or beyond the rest distance. `R_py = 2·μ²·R` with `μ² = friction²/impratio` and `R
    /// = (1 − d)/d·W·(1 + friction²)`, the first facet's (`mj_makeImpedance`, `mj_diagApprox`;
    /// `W` the inverse weight, else `a_normal`, the point's own normal `A`).
    pub fn facet_row(&self, dist: Real, v0: Real, dt: Real, a_normal: Real) -> Option<(Real, Real)> {
        if dist >= self.rest {
            return None;
        }
        let d = self.impedance(dist);
        let (stiffness, damping) = self.gains(dt);
        let aref = -damping * v0 - stiffness * d * (dist - self.rest);
        let weight = if self.invweight > 0.0 {
            self.invweight
        } else {
            a_normal
        };
        let f0 = self.friction.max(MIN_MU);
        let mu2 = f0 * f0 / self.impratio.max(MIN_VAL);
        let reg = 2.0 * mu2 * (1.0 - d) / d * weight * (1.0 + f0 * f0);
        Some((-(v0 + dt * aref), reg))
    }

    /// `(K, B)` at step `dt`: with a time constant under `2·dt` (standard form), those of
    /// `2·dt`, as MuJoCo's `refsafe` makes them (a stiffer spring would not be stable).
    pub fn gains(&self, dt: Real) -> (Real, Real) {
        let [timeconst, dampratio] = self.solref;
        if timeconst > 0.0 && timeconst < 2.0 * dt {
            let safe = Self::new([2.0 * dt, dampratio], self.solimp, self.margin, self.rest);
            (safe.stiffness, safe.damping)
        } else {
            (self.stiffness, self.damping)
        }
    }

    /// `cfm = A/(A + R)` with `R = scale·(1 − d)/d·W`, `W` the inverse weight (MuJoCo's
    /// approximation of `A`), else `A` itself.
    pub fn cfm(&self, d: Real, mass: Real) -> Real {
        if self.invweight > 0.0 {
            let regulariser = self.normal_scale * (1.0 - d) / d * self.invweight;
            1.0 / (1.0 + regulariser * mass)
        } else {
            d / (d + self.normal_scale * (1.0 - d))
        }
    }
}

/// The rhs of a row that must push nothing: `λ = max(0, λ − m·(J·v + rhs))` is zero for any
/// velocity a step can reach (finite, so that a row of zero effective mass stays zero).
pub const SEPARATED_RHS: Real = 1.0e10;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_give_mujoco_gains() {
        let c = PairCompliance::mix(&ContactCompliance::default(), &ContactCompliance::default());
        // K = 1/(0.95²·0.02²·1²), B = 2/(0.95·0.02).
        assert!((c.stiffness - 1.0 / (0.9025 * 0.0004)).abs() < 1e-6 * c.stiffness);
        assert!((c.damping - 2.0 / 0.019).abs() < 1e-9);
        // Deeper than the width: dmax; at the surface: dmin; halfway: the sigmoid's midpoint.
        assert_eq!(c.impedance(-0.01), 0.95);
        assert_eq!(c.impedance(0.0), 0.9);
        assert!((c.impedance(-0.0005) - 0.925).abs() < 1e-6, "f32");
    }

    #[test]
    fn a_time_constant_under_two_steps_is_two_steps() {
        let solimp = [0.9, 0.95, 0.001, 0.5, 2.0];
        let fast = PairCompliance::new([1.0e-5, 1.0], solimp, 0.0, 0.0);
        let safe = PairCompliance::new([0.004, 1.0], solimp, 0.0, 0.0);
        assert_eq!(fast.gains(0.002), (safe.stiffness, safe.damping));
        assert_eq!(fast.row(-0.001, 0.1, 0.002, 2.0), safe.row(-0.001, 0.1, 0.002, 2.0));
        // Slow enough, and the direct form: as given.
        assert_eq!(safe.gains(0.001), (safe.stiffness, safe.damping));
        let direct = PairCompliance::new([-1.0e9, -10.0], solimp, 0.0, 0.0);
        assert_eq!(direct.gains(0.002), (direct.stiffness, direct.damping));
    }

    #[test]
    fn priority_wins_and_solmix_weighs() {
        let soft = ContactCompliance {
            solref: [0.1, 0.5],
            ..Default::default()
        };
        let high = ContactCompliance {
            priority: 1,
            ..Default::default()
        };
        let c = PairCompliance::mix(&soft, &high);
        assert_eq!(c, PairCompliance::mix(&high, &high));
        let heavy = ContactCompliance {
            solmix: 3.0,
            ..soft
        };
        let c = PairCompliance::mix(&heavy, &ContactCompliance::default());
        let solref = [0.75 * 0.1 + 0.25 * 0.02, 0.75 * 0.5 + 0.25 * 1.0];
        let expected = PairCompliance {
            pyramidal: true,
            torsional: 0.005,
            rolling: 0.0001,
            ..PairCompliance::new(solref, DEFAULT_SOLIMP, 0.0, 0.0)
        };
        assert_eq!(c, expected);
        // Direct (negative) form: the smaller of each.
        let direct = ContactCompliance {
            solref: [-1000.0, -10.0],
            ..Default::default()
        };
        let c = PairCompliance::mix(&direct, &ContactCompliance::default());
        assert_eq!(c.stiffness, 1000.0 / (0.95 * 0.95));
        assert_eq!(c.damping, 10.0 / 0.95);
    }

    #[test]
    fn condim_and_the_angular_coefficients_mix_as_mujocos() {
        // Equal priority: the larger condim, and the larger of each coefficient.
        let spin = ContactCompliance {
            condim: 4,
            torsional: 0.002,
            rolling: 0.0,
            ..Default::default()
        };
        let roll = ContactCompliance {
            condim: 6,
            torsional: 0.001,
            rolling: 0.0003,
            ..Default::default()
        };
        let c = PairCompliance::mix(&spin, &roll);
        assert_eq!((c.condim, c.torsional, c.rolling), (6, 0.002, 0.0003));
        assert_eq!(c.angular_friction(), &[0, 1, 1]);
        // A higher priority's, whole.
        let high = ContactCompliance {
            priority: 2,
            ..spin
        };
        let c = PairCompliance::mix(&roll, &high);
        assert_eq!((c.condim, c.torsional, c.rolling), (4, 0.002, 0.0));
        assert_eq!(c.angular_friction(), &[0]);
        // Below 4: no angular rows.
        let plain = ContactCompliance::default();
        assert!(PairCompliance::mix(&plain, &plain).angular_friction().is_empty());
    }

    #[test]
    fn condim_one_is_frictionless_and_the_pyramid_has_its_facets() {
        let one = ContactCompliance {
            condim: 1,
            ..Default::default()
        };
        // Both frictionless: no friction, the normal row regularised by `R` itself.
        let c = PairCompliance::mix(&one, &one).with_friction(0.7);
        assert_eq!((c.friction, c.normal_scale), (0.0, 1.0));
        // One frictionless, one not: the larger condim, 3.
        let c = PairCompliance::mix(&one, &ContactCompliance::default()).with_friction(0.7);
        assert_eq!(c.friction, 0.7);
        // The pyramid's normal row: `R_py/(2·(condim − 1))`, `R_py = 2μ²(1 + μ²)·R`.
        let at = |condim: u8| {
            let k = ContactCompliance {
                condim,
                ..Default::default()
            };
            PairCompliance::mix(&k, &k).with_friction(1.0).normal_scale
        };
        assert_eq!((at(3), at(4), at(6)), (1.0, 2.0 / 3.0, 0.4));
    }

    #[test]
    fn an_angular_row_is_regularised_by_its_coefficient() {
        let k = |pyramidal: bool| ContactCompliance {
            condim: 6,
            pyramidal,
            ..Default::default()
        };
        for pyramidal in [false, true] {
            let c = PairCompliance::mix(&k(pyramidal), &k(pyramidal)).with_friction(0.5);
            let (dist, v0, dt, mass) = (-0.0005, 2.0, 0.002, 0.01);
            let (rhs_t, cfm_t) = c.friction_row(dist, v0, dt, mass);
            let (rhs, cfm) = c.angular_row(dist, v0, dt, mass, 0.005);
            // The same target (the damper alone), `R` scaled by `(μ/μ_j)²`, twice that at the
            // pyramid's edge.
            assert_eq!(rhs, rhs_t);
            let r = |cfm: Real| (1.0 / cfm - 1.0) / mass;
            let scale = (0.5f32 / 0.005).powi(2) * if pyramidal { 2.0 } else { 1.0 };
            assert!((r(cfm) / r(cfm_t) / scale - 1.0).abs() < 1e-3, "{pyramidal}");
        }
        // Beyond the rest distance: a row that pushes nothing, as the sliding rows'.
        let c = PairCompliance::mix(&k(true), &k(true)).with_friction(0.5);
        assert_eq!(c.angular_row(0.01, 2.0, 0.002, 0.01, 0.005), (0.0, 1.0));
    }

    #[test]
    fn margins_add_up_and_rows_beyond_push_nothing() {
        let a = ContactCompliance {
            margin: 0.01,
            gap: 0.004,
            ..Default::default()
        };
        let b = ContactCompliance {
            margin: 0.002,
            ..Default::default()
        };
        let c = PairCompliance::mix(&a, &b);
        assert_eq!((c.margin, c.rest), (0.016, 0.012));
        // In the gap (detected, not acting) and at the rest point: excluded, as MuJoCo has it.
        assert_eq!(c.row(0.014, 0.0, 0.001, 1.0), (SEPARATED_RHS, 1.0));
        assert_eq!(c.row(0.012, 0.0, 0.001, 1.0), (SEPARATED_RHS, 1.0));
        // Below it: a spring pushing out, at the impedance of its depth.
        let (rhs, d) = c.row(0.0, 0.0, 0.001, 1.0);
        assert!(rhs < 0.0 && d == 0.95, "{rhs} {d}");
    }

    #[test]
    fn a_pyramid_is_as_soft_as_the_file_at_unit_friction_and_stiffer_below() {
        let c = PairCompliance::mix(&ContactCompliance::default(), &ContactCompliance::default());
        let (_, at_one) = c.with_friction(1.0).row(-0.01, 0.0, 0.001, 1.0);
        assert_eq!(at_one, 0.95);
        let (_, at_04) = c.with_friction(0.4).row(-0.01, 0.0, 0.001, 1.0);
        let scale = 0.16 * 1.16 / 2.0;
        assert!((at_04 - 0.95 / (0.95 + scale * 0.05)).abs() < 1e-6, "{at_04}");
        let (_, frictionless) = c.with_friction(0.0).row(-0.01, 0.0, 0.001, 1.0);
        assert!(frictionless > 1.0 - 1e-6, "{frictionless}");
        let elliptic = ContactCompliance {
            pyramidal: false,
            ..Default::default()
        };
        let c = PairCompliance::mix(&elliptic, &elliptic).with_friction(0.4);
        assert_eq!(c.row(-0.01, 0.0, 0.001, 1.0).1, 0.95);
    }
}
