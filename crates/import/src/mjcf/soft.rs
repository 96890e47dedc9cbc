//! MuJoCo's compliant contacts: a geom's `solref`, `solimp`, `solmix`, `priority`, `margin`
//! and `gap` (with its classes' defaults and MuJoCo's own) become its material's
//! `soft_contact`, lengths in mm; `<option o_solref o_solimp o_margin>` with
//! `<flag override="enable">` replace every geom's, and `<option cone impratio>` go to each. MuJoCo's run-time rules are applied
//! as it applies them (`getsolparam`): a `solref` of mixed signs becomes the default, a
//! time constant shorter than two timesteps is lengthened to two, and the impedances are
//! clamped into (0, 1).

use std::collections::BTreeMap;

use gymfleet_assembly::{FrictionCone, MaterialDef, SoftContactDef, SoftLimitDef};
use roxmltree::Node;

use super::Converter;
use crate::xml::XmlReader;
use crate::Result;

/// MuJoCo's `mjMINIMP` and `mjMAXIMP`.
const IMPEDANCE_RANGE: (f64, f64) = (0.0001, 0.9999);
const DEFAULT_SOLREF: [f64; 2] = [0.02, 1.0];
const DEFAULT_SOLIMP: [f64; 5] = [0.9, 0.95, 0.001, 0.5, 2.0];
/// MuJoCo's default timestep (s), for its time-constant floor.
const DEFAULT_TIMESTEP: f64 = 0.002;
const MM: f64 = 1000.0;
/// What `cone` and `impratio` change here, for their warnings.
const FRICTION_NOTE: &str = "{} sizes how soft the contacts are, along the normal and in \
    friction, as MuJoCo's; the pyramid is MuJoCo's four facets at condim 3 (its square \
    section at 4 and 6), the ellipse its circle, on which a contact sliding at the edge may \
    move a few degrees off MuJoCo's direction";

/// `<option>`'s contact settings: `cone`, `impratio`, and the override, kept until
/// `<flag override>` is known to be on.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct ContactOptions {
    pub solref: Option<[f64; 2]>,
    pub solimp: Option<[f64; 5]>,
    pub margin: Option<f64>,
    /// `<flag override="enable">`.
    pub enabled: bool,
    /// `cone="elliptic"`.
    pub elliptic: bool,
    pub impratio: Option<f64>,
}

impl<'a, 'i> Converter<'a, 'i> {
    /// `<option>`'s `cone`, `impratio`, `o_solref`, `o_solimp` and `o_margin`.
    pub(super) fn contact_options(&mut self, node: Node<'a, 'i>) -> Result<()> {
        self.contact_options.solref = self.exactly::<2>(node, None, "o_solref")?;
        self.contact_options.solimp = self.exactly::<5>(node, None, "o_solimp")?;
        self.contact_options.margin = self.number(node, None, "o_margin")?;
        match node.attribute("cone") {
            None | Some("pyramidal") => {}
            Some("elliptic") => {
                self.contact_options.elliptic = true;
                self.warn(node, FRICTION_NOTE.replace("{}", "cone=\"elliptic\""));
            }
            Some(other) => {
                return Err(self.bad(
                    node,
                    "cone",
                    format!(
                        "expected pyramidal or elliptic, got {:?}",
                        other.chars().take(40).collect::<String>()
                    ),
                ))
            }
        }
        if let Some(r) = self.number(node, None, "impratio")? {
            if r.is_nan() || r <= 0.0 {
                return Err(self.bad(node, "impratio", format!("expected a ratio > 0, got {r}")));
            }
            self.contact_options.impratio = Some(r);
            self.warn(
                node,
                FRICTION_NOTE.replace("{}", &format!("impratio=\"{r}\"")),
            );
        }
        Ok(())
    }

    /// A `solimp`-shaped attribute: 3 to 5 numbers, the rest MuJoCo's defaults (older
    /// models list the first three only).
    fn solimp_attr(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        attr: &str,
    ) -> Result<Option<[f64; 5]>> {
        match self.numbers(node, class, attr)? {
            None => Ok(None),
            Some(v) if (3..=5).contains(&v.len()) => {
                let mut out = DEFAULT_SOLIMP;
                out[..v.len()].copy_from_slice(&v);
                Ok(Some(out))
            }
            Some(v) => Err(self.bad(
                node,
                attr,
                format!("expected 3 to 5 numbers, got {}", v.len()),
            )),
        }
    }

    /// A geom's compliant contact, as its attributes and classes give it (MuJoCo's defaults
    /// else); `solimp` may list its first three numbers only, as older models do.
    pub(super) fn soft_contact(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
    ) -> Result<SoftContactDef> {
        let solref = self.exactly::<2>(node, class, "solref")?;
        let solimp = self.solimp_attr(node, class, "solimp")?;
        let length = |name: &str| -> Result<Option<f64>> {
            match self.number(node, class, name)? {
                Some(v) if v < 0.0 => {
                    Err(self.bad(node, name, format!("expected a distance >= 0 m, got {v}")))
                }
                v => Ok(v.map(|v| v * MM)),
            }
        };
        let margin = length("margin")?;
        let gap = length("gap")?;
        let solmix = self.number(node, class, "solmix")?;
        if let Some(mix) = solmix.filter(|m| *m < 0.0) {
            return Err(self.bad(node, "solmix", format!("expected a weight >= 0, got {mix}")));
        }
        let priority = match self.number(node, class, "priority")? {
            Some(p) if p.fract() != 0.0 || p.abs() > i32::MAX as f64 => {
                return Err(self.bad(node, "priority", format!("expected an integer, got {p}")))
            }
            p => p.map(|p| p as i32),
        };
        // `condim` and the friction triplet's torsional and rolling coefficients (m).
        let condim = match self.number(node, class, "condim")? {
            None => None,
            Some(c) if [1.0, 3.0, 4.0, 6.0].contains(&c) => Some(c as u32),
            Some(c) => {
                return Err(self.bad(node, "condim", format!("expected 1, 3, 4 or 6, got {c}")))
            }
        };
        let friction = self.numbers(node, class, "friction")?.unwrap_or_default();
        let coefficient = |k: usize, name: &str| -> Result<Option<f64>> {
            match friction.get(k) {
                Some(v) if !(v.is_finite() && *v >= 0.0) => Err(self.bad(
                    node,
                    "friction",
                    format!("expected a {name} coefficient >= 0, got {v}"),
                )),
                v => Ok(v.map(|v| v * MM)),
            }
        };
        let torsional_friction = coefficient(1, "torsional")?;
        let rolling_friction = coefficient(2, "rolling")?;
        Ok(SoftContactDef {
            solref,
            solimp,
            solmix,
            priority,
            margin,
            gap,
            condim,
            torsional_friction,
            rolling_friction,
            // `<option>`'s, set for every geom in `finish_soft_contacts`.
            cone: None,
            impratio: None,
        })
    }
}

impl<'a, 'i> Converter<'a, 'i> {
    /// A limited joint's compliant limits (`solreflimit`, `solimplimit`, `margin`, with its
    /// classes' and MuJoCo's defaults), in degrees for a hinge and mm for a slide.
    pub(super) fn soft_limit(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        hinge: bool,
    ) -> Result<SoftLimitDef> {
        // MuJoCo's joint values are radians and metres whatever `<compiler angle>` says.
        let unit = if hinge {
            180.0 / std::f64::consts::PI
        } else {
            MM
        };
        let solref = self.exactly::<2>(node, class, "solreflimit")?;
        let solimp = self.solimp_attr(node, class, "solimplimit")?;
        let margin = match self.number(node, class, "margin")? {
            Some(v) if v < 0.0 => {
                return Err(self.bad(node, "margin", format!("expected a distance >= 0, got {v}")))
            }
            v => v.unwrap_or(0.0) * unit,
        };
        let mut solimp = solimp.unwrap_or(DEFAULT_SOLIMP);
        clamp_solimp(&mut solimp);
        solimp[2] *= unit;
        Ok(SoftLimitDef {
            solref,
            solimp: Some(solimp),
            margin: Some(margin),
        })
    }
}

/// MuJoCo's run-time bounds on `solimp` (`getsolparam`), the width in its own units.
fn clamp_solimp(solimp: &mut [f64; 5]) {
    let (lo, hi) = IMPEDANCE_RANGE;
    for k in [0, 1, 3] {
        solimp[k] = solimp[k].clamp(lo, hi);
    }
    solimp[2] = solimp[2].max(0.0);
    solimp[4] = solimp[4].max(1.0);
}

/// MuJoCo's `solref` rules at run time (`getsolparam`): mixed signs become the default, a
/// time constant is at least two timesteps, and (here) both zero the default too.
fn safe_solref(solref: Option<[f64; 2]>, timestep: f64) -> [f64; 2] {
    let mut solref = solref.unwrap_or(DEFAULT_SOLREF);
    if (solref[0] > 0.0) != (solref[1] > 0.0) || solref[0] == 0.0 {
        // Both zero: MuJoCo's direct form with no stiffness pushes nothing; the document
        // wants a stiffness, so the default stands in.
        solref = DEFAULT_SOLREF;
    }
    if solref[0] > 0.0 {
        solref[0] = solref[0].max(2.0 * timestep);
    }
    solref
}

/// Applies MuJoCo's run-time rules to every limited joint's `solreflimit`.
pub(super) fn finish_soft_limits(
    joints: &mut [gymfleet_assembly::JointDef],
    timestep: Option<f64>,
) {
    let timestep = timestep.unwrap_or(DEFAULT_TIMESTEP);
    for soft in joints.iter_mut().filter_map(|j| j.soft_limit.as_mut()) {
        soft.solref = Some(safe_solref(soft.solref, timestep));
    }
}

/// Applies `<option>`'s override and MuJoCo's run-time rules to every material's compliant
/// contact, the timestep being `timestep` (s, MuJoCo's default when `None`).
pub(super) fn finish_soft_contacts(
    materials: &mut BTreeMap<String, MaterialDef>,
    over: &ContactOptions,
    timestep: Option<f64>,
) {
    let timestep = timestep.unwrap_or(DEFAULT_TIMESTEP);
    for soft in materials
        .values_mut()
        .filter_map(|m| m.soft_contact.as_mut())
    {
        soft.cone = over.elliptic.then_some(FrictionCone::Elliptic);
        soft.impratio = over.impratio;
        if over.enabled {
            soft.solref = Some(over.solref.unwrap_or(DEFAULT_SOLREF));
            soft.solimp = Some(over.solimp.unwrap_or(DEFAULT_SOLIMP));
            soft.margin = Some(over.margin.unwrap_or(0.0) * MM);
        }
        soft.solref = Some(safe_solref(soft.solref, timestep));
        let mut solimp = soft.solimp.unwrap_or(DEFAULT_SOLIMP);
        clamp_solimp(&mut solimp);
        solimp[2] *= MM;
        soft.solimp = Some(solimp);
    }
}
