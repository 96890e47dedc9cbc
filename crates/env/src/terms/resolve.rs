//! A [`TermsTask`] checked against one env ([`Context`]): names into indices, bounds
//! into ranges, with an error naming the JSON path of each mistake (the coordinates and
//! points: `quantity.rs`).

use std::cell::RefCell;

use gymfleet_assembly::Assembly;
use gymfleet_assembly::DofKind;
use gymfleet_physics::{JointDof, Units};

use super::active::{ActiveHealthy, ActiveSet, ActiveTerms, Dist, Kind, Op};
use super::tolerance;
use super::{
    bad, bounded, shown, ContactCost, Factor, Healthy, Noise, ResetNoise, SetJoints, TermKind,
    TermsTask, MAX_NAME, MAX_TERMS, MAX_VALUE,
};
use crate::error::Result;

/// What the resolver needs from the env.
pub(crate) struct Context<'a> {
    pub(crate) assembly: &'a Assembly,
    pub(crate) dofs: &'a [JointDof],
    /// The action's length (the `action` quantity's bound).
    pub(crate) action_dim: usize,
    pub(crate) units: Units,
    pub(crate) dt: f64,
    /// The groups of instances contact terms read, collected while resolving.
    pub(crate) groups: RefCell<Vec<Vec<usize>>>,
}

/// The index of instance `name`, or an error at `path` listing the known ones.
pub(crate) fn instance(assembly: &Assembly, path: &str, name: &str) -> Result<usize> {
    assembly.instance_index(name).ok_or_else(|| {
        let names: Vec<String> = assembly
            .instances
            .iter()
            .map(|i| format!("{:?}", i.name))
            .collect();
        let shown = names.len().min(16);
        let more = if names.len() > shown {
            format!(" and {} more", names.len() - shown)
        } else {
            String::new()
        };
        let name: String = name.chars().take(64).collect();
        bad(
            path,
            format!(
                "unknown instance {name:?} (known: {}{more})",
                names[..shown].join(", ")
            ),
        )
    })
}

impl super::choice::ChoiceNames for Context<'_> {
    fn one_dof(&self, at: &str, name: &str, seen: &mut Vec<usize>) -> Result<usize> {
        Context::one_dof(self, at, name, seen)
    }

    fn frame(&self, at: &str, name: &str) -> Result<(usize, [f64; 3], [f64; 3])> {
        match self.assembly.site_index(name) {
            Some(_) => self.site_frame(at, name),
            None => Ok((self.instance(at, name)?, [0.0; 3], [0.0; 3])),
        }
    }

    fn angular(&self, dof: usize) -> bool {
        self.dofs[dof].kind == DofKind::Angular
    }
}

impl Context<'_> {
    fn contact_cost(&self, path: &str, c: &ContactCost) -> Result<(Vec<usize>, f64, f64, f64)> {
        if c.groups.len() > self.assembly.instances.len() {
            return Err(bad(
                format!("{path}.groups"),
                format!(
                    "expected at most the number of instances ({}) groups, got {}",
                    self.assembly.instances.len(),
                    c.groups.len()
                ),
            ));
        }
        let lo = bounded(&format!("{path}.min"), c.min, "bound")?;
        let hi = bounded(&format!("{path}.max"), c.max, "bound")?;
        if lo > hi {
            return Err(bad(
                format!("{path}.max"),
                format!("expected max >= min = {}, got {}", shown(lo), shown(hi)),
            ));
        }
        let groups = c
            .groups
            .iter()
            .enumerate()
            .map(|(k, g)| self.group(&format!("{path}.groups[{k}]"), g))
            .collect::<Result<Vec<_>>>()?;
        let sum_max = match c.sum_max {
            Some(m) => bounded(&format!("{path}.sum_max"), m, "bound")?,
            None => f64::INFINITY,
        };
        Ok((groups, lo, hi, sum_max))
    }

    fn set(&self, path: &str, set: &SetJoints, seen: &mut Vec<usize>) -> Result<ActiveSet> {
        let n = set.joints.len();
        if n == 0 || n > MAX_TERMS {
            return Err(bad(
                format!("{path}.joints"),
                format!("expected 1 to {MAX_TERMS} joints, got {n}"),
            ));
        }
        let (normal, low, high) = set_bounds(path, set, n)?;
        let mut dofs = Vec::with_capacity(n);
        for (k, name) in set.joints.iter().enumerate() {
            dofs.push(self.one_dof(&format!("{path}.joints[{k}]"), name, seen)?);
            let (a, b) = if normal {
                ("mean", "std")
            } else {
                ("low", "high")
            };
            let lo = bounded(&format!("{path}.{a}[{k}]"), low[k], "position")?;
            let hi = bounded(&format!("{path}.{b}[{k}]"), high[k], "position")?;
            if normal && hi < 0.0 {
                return Err(bad(
                    format!("{path}.std[{k}]"),
                    format!("expected a standard deviation >= 0, got {}", shown(hi)),
                ));
            }
            if !normal && lo > hi {
                return Err(bad(
                    format!("{path}.high[{k}]"),
                    format!("expected high >= low = {}, got {}", shown(lo), shown(hi)),
                ));
            }
        }
        let min_norm = bounded(
            &format!("{path}.min_norm"),
            set.min_norm.unwrap_or(0.0),
            "norm",
        )?;
        let max_norm = match set.max_norm {
            Some(m) => bounded(&format!("{path}.max_norm"), m, "norm")?,
            None => f64::INFINITY,
        };
        if min_norm < 0.0 || max_norm < min_norm {
            return Err(bad(
                format!("{path}.max_norm"),
                format!(
                    "expected 0 <= min_norm <= max_norm, got {} and {}",
                    shown(min_norm),
                    shown(max_norm)
                ),
            ));
        }
        Ok(ActiveSet {
            dofs,
            normal,
            at_rest: set.at_rest,
            low: low.to_vec(),
            high: high.to_vec(),
            min_norm,
            max_norm,
        })
    }

    /// The DOF of one-DOF joint `name`, which no earlier draw places (`seen`, which it
    /// joins).
    pub(super) fn one_dof(&self, at: &str, name: &str, seen: &mut Vec<usize>) -> Result<usize> {
        let dof = self.joint(at, name)?;
        if self.dofs.iter().filter(|d| d.joint_name == *name).count() != 1 {
            return Err(bad(
                at,
                "expected a joint with one DOF (revolute or prismatic)",
            ));
        }
        if seen.contains(&dof) {
            return Err(bad(at, "the joint is set by an earlier entry too"));
        }
        seen.push(dof);
        Ok(dof)
    }

    /// `reset_noise.equal` resolved: DOF pairs of one kind, the first drawn by nothing else.
    fn equal(&self, pairs: &[[String; 2]], seen: &mut Vec<usize>) -> Result<Vec<(usize, usize)>> {
        let mut out = Vec::with_capacity(pairs.len());
        for (i, [a, b]) in pairs.iter().enumerate() {
            let at = format!("task.terms.reset_noise.equal[{i}]");
            let to = self.joint(&format!("{at}[1]"), b)?;
            let from = self.one_dof(&format!("{at}[0]"), a, seen)?;
            if self.dofs.iter().filter(|d| d.joint_name == *b).count() != 1 {
                return Err(bad(
                    format!("{at}[1]"),
                    "expected a joint with one DOF (revolute or prismatic)",
                ));
            }
            if self.dofs[from].kind != self.dofs[to].kind {
                return Err(bad(
                    at,
                    "expected two joints of one kind (both revolute or both prismatic)",
                ));
            }
            out.push((from, to));
        }
        Ok(out)
    }

    /// dm_control's `randomize_limited_and_rotational_joints` as sets: each limited
    /// one-DOF joint (`limited`) uniform in its range, each unlimited revolute one
    /// (`rotational`) in [−π, π], but the joints an explicit set draws (`seen`).
    fn joint_ranges(&self, noise: &ResetNoise, sets: &mut Vec<ActiveSet>, seen: &[usize]) {
        for (k, dof) in self.dofs.iter().enumerate() {
            let one = self.dofs.iter().filter(|d| d.joint == dof.joint).count() == 1;
            if !one || seen.contains(&k) {
                continue;
            }
            let range = match dof.limits {
                Some([lo, hi]) if noise.limited => {
                    Some([lo, hi].map(|v| self.units.from_document(dof.kind, v + dof.reference)))
                }
                None if noise.rotational && dof.kind == DofKind::Angular => {
                    // ±180° as a document writes it: ±π rad in SI.
                    Some([-180.0, 180.0].map(|v| self.units.from_document(dof.kind, v)))
                }
                _ => None,
            };
            if let Some([low, high]) = range {
                sets.push(ActiveSet {
                    dofs: vec![k],
                    normal: false,
                    at_rest: true,
                    low: vec![low],
                    high: vec![high],
                    min_norm: 0.0,
                    max_norm: f64::INFINITY,
                });
            }
        }
    }

    fn noise(&self, path: &str, noise: Option<Noise>) -> Result<Option<Dist>> {
        let Some(n) = noise else { return Ok(None) };
        let dist =
            match (n.uniform, n.normal) {
                (Some(s), None) => Dist::Uniform(s),
                (None, Some(s)) => Dist::Normal(s),
                _ => return Err(bad(
                    path,
                    "expected exactly one of uniform (half-width) or normal (standard deviation)",
                )),
            };
        let (Dist::Uniform(s) | Dist::Normal(s)) = dist;
        if !(0.0..=MAX_VALUE).contains(&s) {
            return Err(bad(
                path,
                format!(
                    "expected a scale 0 <= s <= {} (the env's units), got {}",
                    shown(MAX_VALUE),
                    shown(s)
                ),
            ));
        }
        Ok((s > 0.0).then_some(dist))
    }
}

impl TermsTask {
    pub(crate) fn resolve(&self, cx: &Context<'_>) -> Result<ActiveTerms> {
        let terms = self.resolve_terms(cx)?;
        let healthy = match &self.healthy {
            None => None,
            Some(h) => Some(cx.healthy(h)?),
        };
        let noise = self.reset_noise.clone().unwrap_or_default();
        let draws = cx.draws(&noise)?;
        let observed = self
            .terms
            .iter()
            .enumerate()
            .filter(|(_, t)| t.observed())
            .map(|(k, _)| k)
            .collect();
        Ok(ActiveTerms {
            observed,
            groups: cx.groups.take(),
            wrenches: Vec::new(),
            sets: draws.sets,
            choice: draws.choice,
            equal: draws.equal,
            previous: vec![0.0; terms.len()],
            step_values: vec![0.0; terms.len()],
            terms,
            healthy,
            units: cx.units,
            dt: cx.dt,
            base_noise: noise.base,
            settle_substeps: noise.settle_substeps,
            turn_base: noise.rotational && cx.assembly.floating_base,
            reject_contacts: noise.reject_contacts,
            mocap_draws: draws.mocaps,
            position_noise: cx.noise("task.terms.reset_noise.position", noise.position)?,
            velocity_noise: cx.noise("task.terms.reset_noise.velocity", noise.velocity)?,
        })
    }

    /// Each term's weight and kind, its names unique and its quantities resolved.
    fn resolve_terms(&self, cx: &Context<'_>) -> Result<Vec<(f64, Kind)>> {
        if self.terms.len() > MAX_TERMS {
            return Err(bad(
                "task.terms.terms",
                format!(
                    "expected at most {MAX_TERMS} terms, got {}",
                    self.terms.len()
                ),
            ));
        }
        let mut terms = Vec::with_capacity(self.terms.len());
        let mut names: Vec<&str> = Vec::new();
        for (i, t) in self.terms.iter().enumerate() {
            let path = format!("task.terms.terms[{i}]");
            if t.name.is_empty()
                || t.name.chars().count() > MAX_NAME
                || t.name.chars().any(char::is_control)
            {
                return Err(bad(
                    format!("{path}.name"),
                    format!("expected a name of 1 to {MAX_NAME} printable characters"),
                ));
            }
            if names.contains(&t.name.as_str()) {
                let name: String = t.name.chars().take(MAX_NAME).collect();
                return Err(bad(
                    format!("{path}.name"),
                    format!("{name:?} names an earlier term too; names must be unique"),
                ));
            }
            let weight = bounded(&format!("{path}.weight"), t.weight, "weight")?;
            let kind = cx.kind(&path, &t.kind, &names, self.healthy.is_some())?;
            names.push(&t.name);
            terms.push((weight, kind));
        }
        Ok(terms)
    }
}

/// A task's reset draws resolved: the joint sets, the choice, the equal pairs and the
/// mocap draws.
struct Draws {
    sets: Vec<ActiveSet>,
    choice: Option<super::choice::ActiveChoice>,
    equal: Vec<(usize, usize)>,
    mocaps: Vec<super::ActiveMocapDraw>,
}

impl Context<'_> {
    /// What a term computes, resolved; `earlier`: the names of the terms before it.
    fn kind(&self, path: &str, kind: &TermKind, earlier: &[&str], healthy: bool) -> Result<Kind> {
        let combine = |op, field: &str, f: &[Factor]| -> Result<Kind> {
            Ok(Kind::Combine {
                op,
                factors: tolerance::factors(&format!("{path}.{field}"), f, earlier)?,
            })
        };
        Ok(match kind {
            TermKind::Velocity(q) => Kind::Velocity(self.quantity(&format!("{path}.velocity"), q)?),
            TermKind::Value { of, .. } => Kind::Value(self.quantity(&format!("{path}.value"), of)?),
            TermKind::Square(sq) => {
                let center = bounded(&format!("{path}.square.center"), sq.center, "centre")?;
                Kind::Square(self.quantity(&format!("{path}.square.of"), &sq.of)?, center)
            }
            TermKind::ContactCost(c) => {
                let (groups, lo, hi, sum_max) =
                    self.contact_cost(&format!("{path}.contact_cost"), c)?;
                Kind::ContactCost {
                    groups,
                    lo,
                    hi,
                    sum_max,
                }
            }
            TermKind::Tolerance(tol) => {
                Kind::Tolerance(tol.resolve(&format!("{path}.tolerance"), earlier)?)
            }
            TermKind::Product(f) => combine(Op::Product, "product", f)?,
            TermKind::Sum(f) => combine(Op::Sum, "sum", f)?,
            TermKind::Norm(f) => combine(Op::Norm, "norm", f)?,
            TermKind::CtrlCost => Kind::CtrlCost,
            TermKind::Healthy if !healthy => {
                return Err(bad(
                    format!("{path}.healthy"),
                    "a healthy term needs the task's healthy conditions (task.terms.healthy)",
                ))
            }
            TermKind::Healthy => Kind::Healthy,
            TermKind::Distance([a, b]) => Kind::Distance([
                self.end(&format!("{path}.distance[0]"), a)?,
                self.end(&format!("{path}.distance[1]"), b)?,
            ]),
        })
    }

    /// The healthy conditions: each range's quantity and open bounds, and the state's.
    fn healthy(&self, h: &Healthy) -> Result<ActiveHealthy> {
        if h.ranges.len() > MAX_TERMS {
            return Err(bad(
                "task.terms.healthy.ranges",
                format!(
                    "expected at most {MAX_TERMS} ranges, got {}",
                    h.ranges.len()
                ),
            ));
        }
        let mut ranges = Vec::with_capacity(h.ranges.len());
        for (i, r) in h.ranges.iter().enumerate() {
            let path = format!("task.terms.healthy.ranges[{i}]");
            let q = self.quantity(&format!("{path}.of"), &r.of)?;
            let lo = match r.min {
                Some(v) => bounded(&format!("{path}.min"), v, "bound")?,
                None => f64::NEG_INFINITY,
            };
            let hi = match r.max {
                Some(v) => bounded(&format!("{path}.max"), v, "bound")?,
                None => f64::INFINITY,
            };
            open_range(&path, lo, hi)?;
            ranges.push((q, lo, hi));
        }
        let state = match &h.state_range {
            None => None,
            Some(s) => {
                let path = "task.terms.healthy.state_range";
                let lo = bounded(&format!("{path}.min"), s.min, "bound")?;
                let hi = bounded(&format!("{path}.max"), s.max, "bound")?;
                open_range(path, lo, hi)?;
                if s.skip_positions > self.dofs.len() {
                    return Err(bad(
                        format!("{path}.skip_positions"),
                        format!(
                            "expected at most the number of DOFs ({}), got {}",
                            self.dofs.len(),
                            s.skip_positions
                        ),
                    ));
                }
                Some((lo, hi, s.skip_positions))
            }
        };
        Ok(ActiveHealthy {
            ranges,
            state,
            terminate: h.terminate,
        })
    }

    /// The reset's draws: the floating base's noise checked, the joint sets, the choice,
    /// the equal pairs, the joints drawn in their ranges and the mocap bodies' starts.
    fn draws(&self, noise: &ResetNoise) -> Result<Draws> {
        if noise.base {
            let path = "task.terms.reset_noise.base";
            if !self.assembly.floating_base {
                return Err(bad(path, "the document has no floating base"));
            }
            if self.units != Units::Si {
                return Err(bad(
                    path,
                    "a floating base's noise is drawn in SI units (metres, radians, a \
                     quaternion's components): create the env with units \"si\"",
                ));
            }
        }
        let mut sets = Vec::with_capacity(noise.set.len());
        let mut seen: Vec<usize> = Vec::new();
        for (i, set) in noise.set.iter().enumerate() {
            sets.push(self.set(&format!("task.terms.reset_noise.set[{i}]"), set, &mut seen)?);
        }
        let choice = match &noise.choice {
            Some(c) => Some(c.resolve("task.terms.reset_noise.choice", self, &mut seen)?),
            None => None,
        };
        let equal = self.equal(&noise.equal, &mut seen)?;
        self.joint_ranges(noise, &mut sets, &seen);
        Ok(Draws {
            sets,
            choice,
            equal,
            mocaps: self.mocap_draws(noise)?,
        })
    }

    /// Where mocap bodies start, each drawn by one entry.
    fn mocap_draws(&self, noise: &ResetNoise) -> Result<Vec<super::ActiveMocapDraw>> {
        let mocaps: Vec<String> = self
            .assembly
            .mocap_bodies()
            .iter()
            .map(|&i| self.assembly.instances[i].name.clone())
            .collect();
        let mut draws = Vec::with_capacity(noise.mocap.len());
        for (i, draw) in noise.mocap.iter().enumerate() {
            let path = format!("task.terms.reset_noise.mocap[{i}]");
            let active = draw.resolve(&path, &mocaps, self.units)?;
            if draws
                .iter()
                .any(|d: &super::ActiveMocapDraw| d.mocap == active.mocap)
            {
                return Err(bad(
                    format!("{path}.body"),
                    "the mocap body is drawn by an earlier entry too",
                ));
            }
            draws.push(active);
        }
        Ok(draws)
    }
}

/// `lo < hi`, or an error at `path.max`.
fn open_range(path: &str, lo: f64, hi: f64) -> Result<()> {
    if lo >= hi {
        return Err(bad(
            format!("{path}.max"),
            format!("expected max > min = {}, got {}", shown(lo), shown(hi)),
        ));
    }
    Ok(())
}

/// A set's bounds: normal draws (`mean`, `std`) or a uniform box (`low`, `high`), one of
/// each per joint.
fn set_bounds<'s>(
    path: &str,
    set: &'s SetJoints,
    n: usize,
) -> Result<(bool, &'s [f64], &'s [f64])> {
    let (normal, low, high) = match (&set.mean, &set.std) {
        (Some(mean), Some(std)) if set.low.is_empty() && set.high.is_empty() => {
            if set.min_norm.is_some() || set.max_norm.is_some() {
                return Err(bad(
                    path,
                    "a normal draw (mean, std) takes no min_norm or max_norm",
                ));
            }
            (true, mean, std)
        }
        (None, None) => (false, &set.low, &set.high),
        _ => {
            return Err(bad(
                path,
                "expected either low and high (a uniform box) or mean and std (normal draws)",
            ))
        }
    };
    if low.len() != n || high.len() != n {
        let (a, b) = if normal {
            ("mean", "std")
        } else {
            ("low", "high")
        };
        return Err(bad(
            path,
            format!(
                "expected one {a} and one {b} per joint ({n}), got {} and {}",
                low.len(),
                high.len()
            ),
        ));
    }
    Ok((normal, low, high))
}
