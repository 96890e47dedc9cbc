//! `<hfield>` assets and `type="hfield"` geoms as MuJoCo reads them: `nrow × ncol`
//! elevations (inline `elevation`, a PNG `file` of the assets, or none: flat), normalised to
//! [0, 1] and scaled by `size[2]` over `x ∈ ±size[0]`, `y ∈ ±size[1]`; the attribute's and
//! the image's first row is at `y = +size[1]` (MuJoCo's `hfield_data` holds them flipped,
//! row 0 at `−size[1]`, which is the document's order). The base, `size[3]` deep, becomes a
//! box under the terrain, its top 1 mm below the terrain's lowest level, so that what stands
//! on flat ground touches the terrain alone.

use super::*;

/// The gap between a heightfield's base box and its lowest level, m.
const BASE_GAP: f64 = 1e-3;

/// One `<hfield>` as read.
#[derive(Debug, Clone)]
pub(super) struct HfieldAsset {
    /// `size`: x and y half-extents, the top elevation and the base depth, m.
    size: [f64; 4],
    /// Rows, columns and the heights in the document's order; none for a file.
    grid: Option<(u32, u32, Vec<f64>)>,
    /// The PNG's path in the assets.
    file: Option<String>,
}

impl<'a, 'i> Converter<'a, 'i> {
    /// Reads one `<hfield>` of `<asset>`.
    pub(super) fn hfield_asset(&mut self, node: Node<'a, 'i>) -> Result<()> {
        let name = node
            .attribute("name")
            .or_else(|| {
                node.attribute("file")
                    .map(|f| f.rsplit('/').next().unwrap_or(f))
            })
            .ok_or_else(|| self.bad(node, "name", "missing".into()))?
            .to_string();
        let size = self
            .exactly::<4>(node, None, "size")?
            .ok_or_else(|| self.bad(node, "size", "missing".into()))?;
        if size[..2].iter().any(|v| !(v.is_finite() && *v > 0.0))
            || size[2..].iter().any(|v| !(v.is_finite() && *v >= 0.0))
        {
            return Err(self.bad(
                node,
                "size",
                format!(
                    "expected x and y half-extents > 0, an elevation and a base ≥ 0, got {size:?}"
                ),
            ));
        }
        let count = |attr: &str| -> Result<u32> {
            match self.number(node, None, attr)? {
                None => Ok(0),
                Some(n) if n >= 0.0 && n.fract() == 0.0 && n <= f64::from(MAX_HEIGHTFIELD_SIDE) => {
                    Ok(n as u32)
                }
                Some(n) => Err(self.bad(
                    node,
                    attr,
                    format!("expected a whole number of 0 to {MAX_HEIGHTFIELD_SIDE}, got {n}"),
                )),
            }
        };
        let (rows, columns) = (count("nrow")?, count("ncol")?);
        let (grid, file) = match node.attribute("file") {
            Some(file) => {
                if rows != 0 || columns != 0 {
                    return Err(self.bad(
                        node,
                        "nrow",
                        "a heightfield from a file takes its size from the image: leave nrow and ncol out".into(),
                    ));
                }
                (None, Some(self.asset_file(node, file)?))
            }
            None => {
                if rows < 2 || columns < 2 {
                    return Err(self.bad(
                        node,
                        "nrow",
                        format!("expected nrow and ncol of at least 2 (or a file), got {rows} and {columns}"),
                    ));
                }
                let points = rows as usize * columns as usize;
                let heights = match self.numbers(node, None, "elevation")? {
                    None => vec![0.0; points],
                    Some(values) if values.len() == points => {
                        hfield_heights(&values, columns as usize)
                    }
                    Some(values) => {
                        return Err(self.bad(
                            node,
                            "elevation",
                            format!(
                                "expected nrow × ncol = {points} numbers, got {}",
                                values.len()
                            ),
                        ))
                    }
                };
                (Some((rows, columns, heights)), None)
            }
        };
        self.hfields.insert(name, HfieldAsset { size, grid, file });
        Ok(())
    }

    /// A `type="hfield"` geom's primitive and the depth of its base (m).
    pub(super) fn hfield_primitive(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
    ) -> Result<(Primitive, f64)> {
        let name = self
            .attr(node, class, "hfield")
            .ok_or_else(|| self.bad(node, "hfield", "missing".into()))?;
        let asset = self
            .hfields
            .get(name)
            .ok_or_else(|| self.bad(node, "hfield", format!("no <hfield> is named {name:?}")))?;
        let [x, y, z, base] = asset.size;
        let (rows, columns, heights) = match &asset.grid {
            Some((r, c, h)) => (Some(*r), Some(*c), Some(h.clone())),
            None => (None, None, None),
        };
        Ok((
            Primitive::Heightfield(HeightfieldDef {
                rows,
                columns,
                size: vec3(DVec3::new(x, y, z) * MM),
                heights,
                file: asset.file.clone(),
            }),
            base,
        ))
    }

    /// The box under a heightfield geom (`size`: its x and y half-extents, m), `base` deep,
    /// its top [`BASE_GAP`] below the terrain's lowest level: a fixed instance of its own
    /// with the geom's collision bits, in the geom's frame `world`.
    pub(super) fn hfield_base(&mut self, geom: &str, world: &Frame, half: [f64; 2], base: f64) {
        let depth = base - BASE_GAP;
        if depth <= 0.0 {
            return;
        }
        let name = self.unique(&format!("{geom}_base"));
        let corner = world.point(DVec3::new(-half[0], -half[1], -base));
        let collision = self
            .instances
            .iter()
            .find(|i| i.name == geom)
            .and_then(|i| i.collision);
        self.parts.push(PartDef {
            name: name.clone(),
            primitive: Primitive::Cube {
                size: vec3(DVec3::new(2.0 * half[0], 2.0 * half[1], depth) * MM),
            },
            material: None,
        });
        self.instances.push(InstanceDef {
            position: Some(vec3(corner * MM)),
            rotation: Some(Vec3::from(euler_xyz_degrees(world.rotation))),
            collision,
            fixed: Some(true),
            ..InstanceDef::new(&name, &name)
        });
        self.massless.insert(name);
    }
}

/// An image's levels (first row at +y) as a document's heights: normalised, row 0 at −y.
pub(crate) fn hfield_heights(levels: &[f64], columns: usize) -> Vec<f64> {
    flipped(&normalised(levels), columns)
}

/// MuJoCo's normalisation: the lowest value 0, the highest 1 (all 0 when they are equal).
fn normalised(values: &[f64]) -> Vec<f64> {
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return vec![0.0; values.len()];
    }
    values.iter().map(|v| (v - lo) / (hi - lo)).collect()
}

/// Rows in the opposite order: an image's (first row at +y) into the document's (row 0 at
/// −y).
fn flipped(values: &[f64], columns: usize) -> Vec<f64> {
    values.chunks(columns).rev().flatten().copied().collect()
}
