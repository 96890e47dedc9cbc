//! Reading MJCF attributes: default classes and childclasses resolved per attribute,
//! numbers, flags and vectors, the compiler's angle unit and settings, `<default>`,
//! `<option>` (gravity and timestep), and frames from `pos` and the orientation attributes.

use super::*;

impl<'a, 'i> Converter<'a, 'i> {
    /// Whether `joint` (a `<freejoint>` or `<joint>` of a body of class `class`) is free.
    pub(super) fn is_free(&self, joint: Node<'a, 'i>, class: Option<&str>) -> bool {
        joint.tag_name().name() == "freejoint" || self.attr(joint, class, "type") == Some("free")
    }

    // --- attributes, with default classes ---------------------------------------------

    /// `node`'s attribute `name`, or its class chain's (`class` attribute, else the
    /// enclosing `childclass`, else the top-level default).
    pub(super) fn attr(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        name: &str,
    ) -> Option<&'a str> {
        if let Some(v) = node.attribute(name) {
            return Some(v);
        }
        let tag = node.tag_name().name();
        let mut current = node
            .attribute("class")
            .map(str::to_string)
            .or_else(|| class.map(str::to_string))
            .or_else(|| Some("main".to_string()));
        while let Some(name_of_class) = current {
            let class = self.classes.get(&name_of_class)?;
            if let Some(v) = class.attributes.get(tag).and_then(|a| a.get(name)) {
                return Some(v);
            }
            current = class.parent.clone();
        }
        None
    }

    pub(super) fn numbers(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        name: &str,
    ) -> Result<Option<Vec<f64>>> {
        let Some(text) = self.attr(node, class, name) else {
            return Ok(None);
        };
        text.split_whitespace()
            .map(|t| {
                t.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        self.bad(node, name, format!("expected finite numbers, got {text:?}"))
                    })
            })
            .collect::<Result<Vec<_>>>()
            .map(Some)
    }

    /// Exactly `n` numbers, if the attribute is there.
    pub(super) fn exactly<const N: usize>(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        name: &str,
    ) -> Result<Option<[f64; N]>> {
        match self.numbers(node, class, name)? {
            None => Ok(None),
            Some(v) => v.clone().try_into().map(Some).map_err(|_| {
                self.bad(node, name, format!("expected {N} numbers, got {}", v.len()))
            }),
        }
    }

    pub(super) fn number(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        name: &str,
    ) -> Result<Option<f64>> {
        Ok(self.exactly::<1>(node, class, name)?.map(|[v]| v))
    }

    pub(super) fn flag(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        name: &str,
    ) -> Result<Option<bool>> {
        match self.attr(node, class, name) {
            None | Some("auto") => Ok(None),
            Some("true") => Ok(Some(true)),
            Some("false") => Ok(Some(false)),
            Some(other) => Err(self.bad(
                node,
                name,
                format!("expected true, false or auto, got {other:?}"),
            )),
        }
    }

    pub(super) fn int(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        name: &str,
        default: u32,
    ) -> Result<u32> {
        match self.attr(node, class, name) {
            None => Ok(default),
            Some(t) => t.trim().parse::<u32>().map_err(|_| {
                self.bad(
                    node,
                    name,
                    format!("expected a non-negative integer, got {t:?}"),
                )
            }),
        }
    }

    pub(super) fn angle(&self, value: f64) -> f64 {
        if self.radian {
            value
        } else {
            value.to_radians()
        }
    }

    // --- settings ------------------------------------------------------------------------

    pub(super) fn compiler(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for a in node.attributes() {
            match (a.name(), a.value()) {
                ("angle", "radian") => self.radian = true,
                ("angle", "degree") => self.radian = false,
                ("inertiafromgeom", "true") => self.inertia_from_geom = InertiaFromGeom::True,
                ("inertiafromgeom", "false") => self.inertia_from_geom = InertiaFromGeom::False,
                ("inertiafromgeom", "auto") => self.inertia_from_geom = InertiaFromGeom::Auto,
                ("settotalmass", value) => {
                    let total: f64 = value.trim().parse().map_err(|_| {
                        self.bad(
                            node,
                            "settotalmass",
                            format!("expected a number, got {value:?}"),
                        )
                    })?;
                    if !total.is_finite() {
                        return Err(self.bad(
                            node,
                            "settotalmass",
                            format!("expected a finite mass, got {value:?}"),
                        ));
                    }
                    // MuJoCo: a positive value rescales every body; others do nothing.
                    self.total_mass = (total > 0.0).then_some(total);
                }
                ("eulerseq", "xyz") | ("coordinate", "local") | ("autolimits", "true") => {}
                ("meshdir", dir) => self.mesh_dir = Some(dir.to_string()),
                ("assetdir", dir) => {
                    self.mesh_dir.get_or_insert_with(|| dir.to_string());
                }
                ("strippath", "true") => self.strip_path = true,
                ("inertiagrouprange", value) => {
                    let range: Vec<i64> = value
                        .split_whitespace()
                        .map(|t| t.parse().ok())
                        .collect::<Option<_>>()
                        .unwrap_or_default();
                    match range[..] {
                        [lo, hi] if lo <= hi => self.inertia_groups = (lo, hi),
                        _ => {
                            return Err(self.bad(
                                node,
                                "inertiagrouprange",
                                format!("expected two integers, lowest first, got {value:?}"),
                            ))
                        }
                    }
                }
                ("texturedir" | "discardvisual" | "strippath", _) => {}
                (name @ ("angle" | "inertiafromgeom"), value) => {
                    return Err(self.bad(node, name, format!("unexpected value {value:?}")))
                }
                (name, value) => {
                    return Err(
                        self.unsupported(node, format!("{name}=\"{value}\" is not supported yet"))
                    )
                }
            }
        }
        Ok(())
    }

    pub(super) fn defaults(&mut self, node: Node<'a, 'i>, parent: Option<&str>) -> Result<()> {
        let name = match (node.attribute("class"), parent) {
            (Some(n), _) => n.to_string(),
            (None, None) => "main".to_string(),
            (None, Some(_)) => {
                return Err(self.bad(
                    node,
                    "class",
                    "a nested <default> needs a class name".into(),
                ))
            }
        };
        let mut class = Class {
            parent: parent.map(str::to_string),
            attributes: HashMap::new(),
            actuator_tags: Vec::new(),
        };
        for child in elements(node) {
            let tag = child.tag_name().name();
            if tag == "default" {
                continue;
            }
            if actuators::is_actuator(tag) && !class.actuator_tags.contains(&tag) {
                class.actuator_tags.push(tag);
            }
            let map = class.attributes.entry(tag).or_default();
            for a in child.attributes() {
                map.insert(a.name(), a.value());
            }
        }
        self.classes.insert(name.clone(), class);
        for child in elements(node).filter(|c| c.tag_name().name() == "default") {
            self.defaults(child, Some(&name))?;
        }
        Ok(())
    }

    /// `<option>`: gravity and timestep become the document's `simulation` (one env step
    /// of the default `dt` is one MuJoCo step), density and viscosity its `fluid` (MuJoCo's
    /// inertia-box model), and `integrator` its `integrator` (`Euler`, MuJoCo's default, as
    /// `euler`; `implicit` and `implicitfast` as `implicit`, and `RK4`, which gymfleet does
    /// not have, as `implicit` with a warning); the rest is the engine's own.
    pub(super) fn option(&mut self, node: Node<'a, 'i>) -> Result<()> {
        if let Some(g) = self.exactly::<3>(node, None, "gravity")? {
            self.simulation.gravity = Some(Vec3::from(g));
        }
        if let Some(t) = self.number(node, None, "timestep")? {
            if !(t > 0.0 && t <= 1.0) {
                return Err(self.bad(node, "timestep", format!("expected (0, 1] s, got {t}")));
            }
            self.simulation.dt = Some(t);
        }
        let mut fluid = FluidDef {
            density: None,
            viscosity: None,
        };
        for name in ["density", "viscosity"] {
            if let Some(v) = self.number(node, None, name)? {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(self.bad(node, name, format!("expected a number ≥ 0, got {v}")));
                }
                if v > 0.0 {
                    let slot = match name {
                        "density" => &mut fluid.density,
                        _ => &mut fluid.viscosity,
                    };
                    *slot = Some(v);
                }
            }
        }
        if fluid.density.is_some() || fluid.viscosity.is_some() {
            self.simulation.fluid = Some(fluid);
        }
        if let Some(integrator) = node.attribute("integrator") {
            self.simulation.integrator = Some(match integrator {
                "Euler" => Integrator::Euler,
                "implicit" | "implicitfast" => Integrator::Implicit,
                "RK4" => {
                    self.warn(
                        node,
                        "integrator=\"RK4\" integrates as \"implicit\" (no RK4 here)".into(),
                    );
                    Integrator::Implicit
                }
                other => {
                    return Err(self.bad(
                        node,
                        "integrator",
                        format!(
                            "expected Euler, RK4, implicit or implicitfast, got {:?}",
                            other.chars().take(40).collect::<String>()
                        ),
                    ))
                }
            });
        }
        if let Some(m) = self.exactly::<3>(node, None, "magnetic")? {
            self.simulation.magnetic = Some(Vec3::from(m));
        }
        if let Some(w) = self.exactly::<3>(node, None, "wind")? {
            if w != [0.0; 3] {
                return Err(self.unsupported(node, "wind is not supported yet".into()));
            }
        }
        self.contact_options(node)?;
        for a in node.attributes() {
            if !READ_OPTIONS.contains(&a.name()) {
                let how = option_approximation(a.name());
                self.warn(
                    node,
                    format!("{}=\"{}\" ignored: {how}", a.name(), a.value()),
                );
            }
        }
        for child in elements(node) {
            match child.tag_name().name() {
                "flag" => self.flags(child)?,
                other => self.warn(child, format!("<{other}> in <option> ignored")),
            }
        }
        Ok(())
    }

    /// `<option><flag>`: `contact`, `constraint`, `limit`, `equality` and `gravity`
    /// switched off are honoured (no contacts, no joint or tendon limits, no equality
    /// constraints, no gravity); the others are warned about, each with what it changes.
    fn flags(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for a in node.attributes() {
            let (name, value) = (a.name(), a.value());
            if !matches!(value, "enable" | "disable") {
                return Err(self.bad(
                    node,
                    name,
                    format!(
                        "expected enable or disable, got {:?}",
                        value.chars().take(40).collect::<String>()
                    ),
                ));
            }
            // MuJoCo's defaults: these few are off, every other flag is on.
            let on_by_default = !matches!(
                name,
                "override" | "energy" | "fwdinv" | "invdiscrete" | "multiccd" | "island"
            );
            if (value == "enable") == on_by_default {
                continue;
            }
            match name {
                "override" => self.contact_options.enabled = true,
                "contact" => self.switched_off.contacts = true,
                "limit" => self.switched_off.limits = true,
                "equality" => self.switched_off.equalities = true,
                "constraint" => {
                    self.switched_off.contacts = true;
                    self.switched_off.limits = true;
                    self.switched_off.equalities = true;
                }
                "gravity" => self.simulation.gravity = Some(Vec3::from([0.0; 3])),
                "energy" | "fwdinv" | "invdiscrete" | "sensornoise" | "sensor" | "midphase"
                | "eulerdamp" | "autoreset" | "nativeccd" | "island" | "multiccd" | "warmstart"
                | "refsafe" => self.warn(
                    node,
                    format!(
                        "{name}=\"{value}\" ignored (no effect on the motion gymfleet simulates)"
                    ),
                ),
                _ => self.warn(
                    node,
                    format!("{name}=\"{value}\" ignored: {}", flag_note(name)),
                ),
            }
        }
        Ok(())
    }

    /// A frame from `pos` and one of `quat`, `euler`, `axisangle`, `xyaxes`, `zaxis` (MuJoCo's
    /// defaults).
    pub(super) fn local_frame(&self, node: Node<'a, 'i>, class: Option<&str>) -> Result<Frame> {
        let p = self.exactly::<3>(node, class, "pos")?.unwrap_or([0.0; 3]);
        let given: Vec<&str> = ["quat", "euler", "axisangle", "xyaxes", "zaxis"]
            .into_iter()
            .filter(|a| node.attribute(*a).is_some())
            .collect();
        if given.len() > 1 {
            return Err(self.bad(
                node,
                given[1],
                format!("an orientation is given twice ({})", given.join(", ")),
            ));
        }
        let rotation = match given.first().copied() {
            None => DQuat::IDENTITY,
            Some(form) => self.orientation(node, class, form)?,
        };
        Ok(Frame {
            translation: DVec3::from_array(p),
            rotation,
        })
    }

    /// An element's orientation given in `form` (`quat`, `euler`, `axisangle`, `zaxis` or
    /// `xyaxes`), as MuJoCo reads each.
    fn orientation(&self, node: Node<'a, 'i>, class: Option<&str>, form: &str) -> Result<DQuat> {
        Ok(match form {
            "quat" => {
                let [w, x, y, z] = self
                    .exactly::<4>(node, class, "quat")?
                    .unwrap_or([1.0, 0.0, 0.0, 0.0]);
                let q = DQuat::from_xyzw(x, y, z, w);
                if q.length() < 1e-9 {
                    return Err(self.bad(
                        node,
                        "quat",
                        "the zero quaternion is no rotation".into(),
                    ));
                }
                q.normalize()
            }
            "euler" => {
                // MuJoCo's default eulerseq "xyz": intrinsic x, then y, then z.
                let [a, b, c] = self.exactly::<3>(node, class, "euler")?.unwrap_or([0.0; 3]);
                DQuat::from_rotation_x(self.angle(a))
                    * DQuat::from_rotation_y(self.angle(b))
                    * DQuat::from_rotation_z(self.angle(c))
            }
            "axisangle" => {
                let [x, y, z, angle] = self
                    .exactly::<4>(node, class, "axisangle")?
                    .unwrap_or([0.0, 0.0, 1.0, 0.0]);
                let axis = DVec3::new(x, y, z);
                if axis.length() < 1e-12 {
                    return Err(self.bad(node, "axisangle", "the axis is the zero vector".into()));
                }
                DQuat::from_axis_angle(axis.normalize(), self.angle(angle))
            }
            "zaxis" => {
                let [x, y, z] = self
                    .exactly::<3>(node, class, "zaxis")?
                    .unwrap_or([0.0, 0.0, 1.0]);
                let axis = DVec3::new(x, y, z);
                if axis.length() < 1e-12 {
                    return Err(self.bad(node, "zaxis", "the axis is the zero vector".into()));
                }
                z_onto(axis.normalize())
            }
            "xyaxes" => {
                // MuJoCo's rule: x normalized, y made orthogonal to x, z = x × y.
                let [x0, x1, x2, y0, y1, y2] = self
                    .exactly::<6>(node, class, "xyaxes")?
                    .unwrap_or([1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
                let x = DVec3::new(x0, x1, x2);
                let y = DVec3::new(y0, y1, y2);
                if x.length() < 1e-12 {
                    return Err(self.bad(node, "xyaxes", "the x axis is the zero vector".into()));
                }
                let x = x.normalize();
                let y = y - x * x.dot(y);
                if y.length() < 1e-12 {
                    return Err(self.bad(
                        node,
                        "xyaxes",
                        "the y axis is zero or parallel to the x axis".into(),
                    ));
                }
                let y = y.normalize();
                DQuat::from_mat3(&DMat3::from_cols(x, y, x.cross(y))).normalize()
            }
            other => {
                return Err(
                    self.unsupported(node, format!("{other} orientations are not supported yet"))
                )
            }
        })
    }
}

/// The `<option>` attributes `option` reads (with `contact_options`' in `soft.rs`).
const READ_OPTIONS: [&str; 12] = [
    "timestep",
    "gravity",
    "density",
    "viscosity",
    "wind",
    "integrator",
    "magnetic",
    "o_solref",
    "o_solimp",
    "o_margin",
    "cone",
    "impratio",
];

/// How an `<option>` attribute gymfleet does not model is approximated, for its warning.
fn option_approximation(name: &str) -> &'static str {
    match name {
        "noslip_iterations" | "noslip_tolerance" => "there is no noslip pass; Rapier's contact solver runs once per substep",
        "iterations" | "ls_iterations" | "tolerance" | "ls_tolerance" | "solver" | "jacobian" | "ccd_iterations" | "ccd_tolerance" | "sdf_iterations" | "sdf_initpoints" => {
            "the solver is Rapier's: one pass per substep (more for kinematic loops), no line search"
        }
        "o_friction" => "the override replaces solref, solimp and margin; each contact keeps its geoms' friction",
        "apirate" | "actuatorgroupdisable" => "no effect on the motion gymfleet simulates",
        "collision" => "every geom pair that contype/conaffinity allow is collided, and every <pair>",
        "mpr_tolerance" | "mpr_iterations" => "collision detection is Rapier's (parry)",
        _ => "not modelled",
    }
}

/// What gymfleet does instead of an `<option><flag>` setting it does not switch, for its
/// warning.
fn flag_note(name: &str) -> &'static str {
    match name {
        "frictionloss" => "joints' and tendons' dry friction still acts",
        "spring" | "damper" => "joint springs and dampers still act",
        "actuation" => "actuators still act",
        "passive" => "passive forces still act",
        "clampctrl" => "controls are still bounded where the model bounds them",
        "filterparent" => "a body still never collides with its parent",
        _ => "gymfleet keeps its default",
    }
}
