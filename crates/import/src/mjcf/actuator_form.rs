//! One actuator element read into MuJoCo's general form, as MuJoCo's XML reader does
//! (`OneActuator`): the attributes every actuator has, then its tag's shortcut (`mjs_setTo*`)
//! over what its class's default already holds.

use super::*;

/// The gain, bias and dynamics types of MuJoCo's that gymfleet computes (the others are
/// refused as they are read).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Type {
    None,
    Fixed,
    Affine,
    Integrator,
    Filter,
    FilterExact,
}

/// The general form of one actuator (MuJoCo's `mjsActuator`, the parts gymfleet reads).
#[derive(Debug, Clone)]
pub(super) struct General {
    pub(super) gaintype: Type,
    pub(super) biastype: Type,
    pub(super) dyntype: Type,
    pub(super) gainprm: [f64; 3],
    pub(super) biasprm: [f64; 3],
    /// `dynprm[0]`: a filter's time constant.
    pub(super) timeconst: f64,
    pub(super) gear: f64,
    pub(super) ctrlrange: [f64; 2],
    pub(super) forcerange: [f64; 2],
    pub(super) actrange: [f64; 2],
    pub(super) ctrllimited: Option<bool>,
    pub(super) forcelimited: Option<bool>,
    pub(super) actlimited: Option<bool>,
    pub(super) actearly: bool,
    /// A tag gymfleet does not compute (`<muscle>`, `<adhesion>`, …).
    pub(super) unsupported: Option<&'static str>,
}

impl Default for General {
    /// MuJoCo's defaults.
    fn default() -> Self {
        General {
            gaintype: Type::Fixed,
            biastype: Type::None,
            dyntype: Type::None,
            gainprm: [1.0, 0.0, 0.0],
            biasprm: [0.0; 3],
            timeconst: 1.0,
            gear: 1.0,
            ctrlrange: [0.0; 2],
            forcerange: [0.0; 2],
            actrange: [0.0; 2],
            ctrllimited: None,
            forcelimited: None,
            actlimited: None,
            actearly: false,
            unsupported: None,
        }
    }
}

/// Attribute lookup: an element's own, or a default class's for one tag.
pub(super) type Lookup<'x> = dyn Fn(&str) -> Option<&'x str> + 'x;

/// Reading one element's (or default's) attributes; errors name `element`, the actuator
/// being read.
struct Read<'r, 'a, 'i, 'x> {
    c: &'r Converter<'a, 'i>,
    element: Node<'a, 'i>,
    get: &'r Lookup<'x>,
}

impl Read<'_, '_, '_, '_> {
    fn text(&self, name: &str) -> Option<&str> {
        (self.get)(name)
    }

    fn nums(&self, name: &str) -> Result<Option<Vec<f64>>> {
        let Some(text) = self.text(name) else {
            return Ok(None);
        };
        text.split_whitespace()
            .map(|t| t.parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect::<Option<Vec<f64>>>()
            .filter(|v| !v.is_empty())
            .map(Some)
            .ok_or_else(|| {
                self.c.bad(
                    self.element,
                    name,
                    format!("expected finite numbers, got {text:?}"),
                )
            })
    }

    fn one(&self, name: &str) -> Result<Option<f64>> {
        Ok(self.nums(name)?.map(|v| v[0]))
    }

    fn pair(&self, name: &str) -> Result<Option<[f64; 2]>> {
        match self.nums(name)? {
            None => Ok(None),
            Some(v) if v.len() == 2 => Ok(Some([v[0], v[1]])),
            Some(v) => Err(self.c.bad(
                self.element,
                name,
                format!("expected 2 numbers, got {}", v.len()),
            )),
        }
    }

    /// `true`, `false` or `auto` (`Some(None)`), if given.
    fn limited(&self, name: &str) -> Result<Option<Option<bool>>> {
        match self.text(name) {
            None => Ok(None),
            Some("auto") => Ok(Some(None)),
            Some("true") => Ok(Some(Some(true))),
            Some("false") => Ok(Some(Some(false))),
            Some(other) => Err(self.c.bad(
                self.element,
                name,
                format!("expected true, false or auto, got {other:?}"),
            )),
        }
    }

    fn not_negative(&self, name: &str, v: f64) -> Result<f64> {
        if v < 0.0 {
            return Err(self
                .c
                .bad(self.element, name, format!("cannot be negative, got {v}")));
        }
        Ok(v)
    }

    fn unsupported(&self, reason: String) -> ImportError {
        self.c.unsupported(self.element, reason)
    }
}

/// Writes one actuator element's attributes (`get`) into `g`, as MuJoCo's reader does for
/// its tag. Errors name `element` (the actuator being read).
pub(super) fn apply(
    c: &Converter<'_, '_>,
    element: Node<'_, '_>,
    tag: &'static str,
    get: &Lookup<'_>,
    g: &mut General,
) -> Result<()> {
    let r = Read { c, element, get };
    common(&r, g)?;
    match tag {
        "general" => general(&r, g)?,
        "motor" => {
            g.gainprm[0] = 1.0;
            g.dyntype = Type::None;
            g.gaintype = Type::Fixed;
            g.biastype = Type::None;
        }
        "position" | "intvelocity" => position(&r, g, tag == "intvelocity")?,
        "velocity" => {
            let kv = r.one("kv")?.unwrap_or(g.gainprm[0]);
            g.biasprm = [0.0, 0.0, -kv];
            g.gainprm[0] = kv;
            g.dyntype = Type::None;
            g.gaintype = Type::Fixed;
            g.biastype = Type::Affine;
        }
        "damper" => {
            let inherited = g.gaintype == Type::Affine;
            let kv = r
                .one("kv")?
                .unwrap_or(if inherited { -g.gainprm[2] } else { 0.0 });
            g.gainprm = [0.0, 0.0, -r.not_negative("kv", kv)?];
            g.ctrllimited = Some(true);
            g.dyntype = Type::None;
            g.gaintype = Type::Affine;
            g.biastype = Type::None;
        }
        "cylinder" => cylinder(&r, g)?,
        _ => {
            g.unsupported = Some(match tag {
                "muscle" => "muscle actuators are not supported yet (MuJoCo's muscle model: its length–force and velocity curves)",
                "adhesion" => "adhesion actuators are not supported (they act on contacts)",
                _ => "this actuator type is not supported (supported: motor, position, velocity, intvelocity, damper, cylinder, general)",
            });
        }
    }
    Ok(())
}

/// The attributes every actuator reads: gear, the ranges and their flags, and the ones
/// refused or warned about.
fn common(r: &Read<'_, '_, '_, '_>, g: &mut General) -> Result<()> {
    if let Some(v) = r.nums("gear")? {
        g.gear = v[0];
        if v[1..].iter().any(|x| *x != 0.0) {
            return Err(r.unsupported(format!(
                "gear {v:?}: only the first component of a gear is used by joint and tendon transmissions"
            )));
        }
    }
    for (name, range) in [
        ("ctrlrange", &mut g.ctrlrange),
        ("forcerange", &mut g.forcerange),
        ("actrange", &mut g.actrange),
    ] {
        if let Some(v) = r.pair(name)? {
            *range = v;
        }
    }
    for (name, flag) in [
        ("ctrllimited", &mut g.ctrllimited),
        ("forcelimited", &mut g.forcelimited),
        ("actlimited", &mut g.actlimited),
    ] {
        if let Some(v) = r.limited(name)? {
            *flag = v;
        }
    }
    // `inheritrange` (a range from the joint's, written into ctrlrange by MuJoCo's
    // compiler), from the element or its class: 0 is MuJoCo's "off".
    if let Some(v) = r
        .text("inheritrange")
        .filter(|v| v.trim().parse::<f64>() != Ok(0.0))
    {
        return Err(r.c.bad(
            r.element,
            "inheritrange",
            format!("{v:?}: inheritrange is not supported yet; give ctrlrange"),
        ));
    }
    if let Some(v) = r.text("actearly") {
        g.actearly = v == "true";
    }
    if let Some(v) = r.text("actdim") {
        if !matches!(v.trim(), "-1" | "0" | "1") {
            return Err(r.unsupported(format!(
                "actdim {v:?}: an actuator has one activation at most here"
            )));
        }
    }
    Ok(())
}

/// `<general>`: the types and their parameters as written.
fn general(r: &Read<'_, '_, '_, '_>, g: &mut General) -> Result<()> {
    for (name, slot, allowed) in [
        ("gaintype", &mut g.gaintype, &["fixed", "affine"][..]),
        ("biastype", &mut g.biastype, &["none", "affine"][..]),
        (
            "dyntype",
            &mut g.dyntype,
            &["none", "integrator", "filter", "filterexact"][..],
        ),
    ] {
        let Some(v) = r.text(name) else { continue };
        if !allowed.contains(&v) {
            return Err(r.unsupported(format!(
                "{name} {v:?} is not supported (supported: {})",
                allowed.join(", ")
            )));
        }
        *slot = match v {
            "none" => Type::None,
            "fixed" => Type::Fixed,
            "affine" => Type::Affine,
            "integrator" => Type::Integrator,
            "filter" => Type::Filter,
            _ => Type::FilterExact,
        };
    }
    for (name, slot) in [("gainprm", &mut g.gainprm), ("biasprm", &mut g.biasprm)] {
        let Some(v) = r.nums(name)? else { continue };
        if v.iter().skip(3).any(|x| *x != 0.0) {
            return Err(r.unsupported(format!(
                "{name} {v:?}: only the first three parameters are used by the affine form"
            )));
        }
        *slot = [0.0; 3];
        for (k, x) in v.iter().take(3).enumerate() {
            slot[k] = *x;
        }
    }
    if let Some(v) = r.nums("dynprm")? {
        g.timeconst = v[0];
    }
    Ok(())
}

/// `<position>` and `<intvelocity>` (`mjs_setToPosition`, `mjs_setToIntVelocity`): a
/// positive `biasprm[2]` is a damping ratio, resolved when the world is built.
fn position(r: &Read<'_, '_, '_, '_>, g: &mut General, integrated: bool) -> Result<()> {
    let kp = r.one("kp")?.unwrap_or(g.gainprm[0]);
    let kv = r.one("kv")?;
    let dampratio = r.one("dampratio")?;
    if kv.is_some() && dampratio.is_some() {
        return Err(r.c.bad(
            r.element,
            "dampratio",
            "kv and dampratio cannot both be defined".into(),
        ));
    }
    g.gainprm[0] = kp;
    g.biasprm[1] = -kp;
    if let Some(kv) = kv {
        g.biasprm[2] = -r.not_negative("kv", kv)?;
    }
    if let Some(d) = dampratio {
        g.biasprm[2] = r.not_negative("dampratio", d)?;
    }
    if let Some(t) = r.one("timeconst")? {
        g.timeconst = r.not_negative("timeconst", t)?;
        g.dyntype = if t == 0.0 {
            Type::None
        } else {
            Type::FilterExact
        };
    }
    g.gaintype = Type::Fixed;
    g.biastype = Type::Affine;
    if integrated {
        g.dyntype = Type::Integrator;
    }
    Ok(())
}

/// `<cylinder>` (`mjs_setToCylinder`): area (or bore) × a filtered control, plus a bias.
fn cylinder(r: &Read<'_, '_, '_, '_>, g: &mut General) -> Result<()> {
    g.timeconst = r.one("timeconst")?.unwrap_or(g.timeconst);
    if let Some(v) = r.nums("bias")? {
        for (k, x) in v.iter().take(3).enumerate() {
            g.biasprm[k] = *x;
        }
    }
    let mut area = r.one("area")?.unwrap_or(g.gainprm[0]);
    if let Some(d) = r.one("diameter")? {
        area = std::f64::consts::PI / 4.0 * d * d;
    }
    g.gainprm[0] = area;
    g.dyntype = Type::Filter;
    g.gaintype = Type::Fixed;
    g.biastype = Type::Affine;
    Ok(())
}
