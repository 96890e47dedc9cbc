//! `<contact>`: `<exclude body1 body2>` keeps every instance of one body from colliding
//! with every instance of the other (`assembly.contacts.exclude`), and `<pair geom1 geom2>`
//! makes two geoms collide whatever their `contype`/`conaffinity` say, with the pair's own
//! friction (MuJoCo's default 1) and `condim` (1: frictionless; 3; 4 and 6, whose torsional
//! and rolling friction gymfleet does not simulate, as 3 with a warning). Read after
//! `<worldbody>`, whose bodies and geoms they name.

use gymfleet_assembly::{ContactExcludeDef, ContactPairDef, ContactsDef};

use super::*;

impl<'a, 'i> Converter<'a, 'i> {
    /// Reads one `<contact>`.
    pub(super) fn contacts(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for child in elements(node) {
            match child.tag_name().name() {
                "exclude" => self.exclude(child)?,
                "pair" => self.pair(child)?,
                other => {
                    return Err(self.unsupported(
                        child,
                        format!("<{other}> in <contact> is not supported (exclude and pair are)"),
                    ))
                }
            }
        }
        Ok(())
    }

    fn exclude(&mut self, node: Node<'a, 'i>) -> Result<()> {
        let first = self.body_instances(node, "body1")?;
        let second = self.body_instances(node, "body2")?;
        let rules = &mut self.contact_rules.exclude;
        for a in &first {
            for b in second.iter().filter(|b| *b != a) {
                rules.push(ContactExcludeDef {
                    a: a.clone(),
                    b: b.clone(),
                });
            }
        }
        Ok(())
    }

    fn pair(&mut self, node: Node<'a, 'i>) -> Result<()> {
        let class = node.attribute("class");
        let a = self.geom_instance(node, "geom1")?;
        let b = self.geom_instance(node, "geom2")?;
        let condim = self.int(node, class, "condim", 3)?;
        let condim = match condim {
            1 | 3 => condim,
            4 | 6 => {
                self.warn(
                    node,
                    format!("condim=\"{condim}\" collides as 3: torsional and rolling friction are not simulated"),
                );
                3
            }
            other => {
                return Err(self.bad(
                    node,
                    "condim",
                    format!("expected 1, 3, 4 or 6, got {other}"),
                ))
            }
        };
        let friction = match self.numbers(node, class, "friction")? {
            Some(f) if f.is_empty() => return Err(self.bad(node, "friction", "no value".into())),
            Some(f) => f[0],
            None => 1.0,
        };
        for attr in ["solref", "solimp", "solreffriction", "margin", "gap"] {
            if self.attr(node, class, attr).is_some() {
                self.warn(node, format!("{attr} ignored (gymfleet's contact model)"));
            }
        }
        self.contact_rules.pairs.push(ContactPairDef {
            a,
            b,
            friction: (condim == 3).then_some(friction),
            condim: Some(condim),
        });
        Ok(())
    }

    /// The instances of the body an `<exclude>` names in `attribute` (the world's: its
    /// geoms).
    fn body_instances(&self, node: Node<'a, 'i>, attribute: &str) -> Result<Vec<String>> {
        let name = node
            .attribute(attribute)
            .ok_or_else(|| self.bad(node, attribute, "missing".into()))?;
        match self.body_instances.get(name) {
            Some(instances) => Ok(instances.clone()),
            // A world without geoms has nothing to exclude.
            None if name == "world" => Ok(Vec::new()),
            None => Err(self.bad(node, attribute, format!("no body is named {name:?}"))),
        }
    }

    /// The instance of the geom a `<pair>` names in `attribute`.
    fn geom_instance(&self, node: Node<'a, 'i>, attribute: &str) -> Result<String> {
        let name = node
            .attribute(attribute)
            .ok_or_else(|| self.bad(node, attribute, "missing".into()))?;
        self.geom_instances.get(name).cloned().ok_or_else(|| {
            self.bad(
                node,
                attribute,
                format!("no geom is named {name:?} (or it was dropped: a massless geom that collides with nothing)"),
            )
        })
    }

    /// The contact rules read so far, for the document (`None` without any).
    pub(super) fn contacts_def(&mut self) -> Option<ContactsDef> {
        let rules = std::mem::take(&mut self.contact_rules);
        (!rules.exclude.is_empty() || !rules.pairs.is_empty()).then_some(rules)
    }
}
