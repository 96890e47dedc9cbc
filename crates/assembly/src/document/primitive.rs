//! [`Primitive`]'s hand-written `Deserialize`: the `type` tag may come after the fields,
//! unknown and duplicate fields are refused with serde's own wording, and every error
//! keeps its exact JSON path (`serde_path_to_error`), e.g. `parts[0].primitive.size.z`.

use serde::de::{self, DeserializeSeed, Deserializer, IgnoredAny, MapAccess, Visitor};
use serde::Deserialize;

use super::{HeightfieldDef, MeshDef, Primitive, Vec3};

/// The `type` tag of a [`Primitive`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
enum PrimitiveKind {
    Cube,
    Cylinder,
    Sphere,
    Capsule,
    Ellipsoid,
    Mesh,
    Plane,
    Heightfield,
}

impl PrimitiveKind {
    /// The fields a primitive of this kind has besides `type`.
    fn fields(self) -> &'static [&'static str] {
        match self {
            PrimitiveKind::Cube => &["size"],
            PrimitiveKind::Cylinder | PrimitiveKind::Capsule => &["radius", "height"],
            PrimitiveKind::Sphere => &["radius"],
            PrimitiveKind::Ellipsoid => &["radii"],
            PrimitiveKind::Mesh => MESH_FIELDS,
            PrimitiveKind::Plane => &[],
            PrimitiveKind::Heightfield => &["rows", "columns", "size", "heights", "file"],
        }
    }
}

/// Every field of any primitive, for unknown-field messages before the tag is known.
const PRIMITIVE_FIELDS: &[&str] = &[
    "type", "size", "radius", "radii", "height", "vertices", "indices", "convex", "file", "scale",
    "rows", "columns", "heights",
];

/// The fields of a mesh primitive besides `type`.
const MESH_FIELDS: &[&str] = &["vertices", "indices", "convex", "file", "scale"];

/// A seed that rejects a map value with an error. Failing *inside* `next_value_seed`
/// makes `serde_path_to_error` report the path of the offending key itself.
struct Reject(String);

impl<'de> DeserializeSeed<'de> for Reject {
    type Value = ();

    fn deserialize<D: Deserializer<'de>>(self, _: D) -> Result<(), D::Error> {
        Err(de::Error::custom(self.0))
    }
}

fn unknown_field_message(field: &str, expected: &'static [&'static str]) -> String {
    use de::Error as _;
    // Reuse serde's own wording ("unknown field `x`, expected one of ...").
    serde::de::value::Error::unknown_field(field, expected).to_string()
}

impl<'de> Deserialize<'de> for Primitive {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_map(PrimitiveVisitor)
    }
}

struct PrimitiveVisitor;

impl<'de> Visitor<'de> for PrimitiveVisitor {
    type Value = Primitive;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(
            "a primitive object with a \"type\" of cube, cylinder, sphere, capsule, ellipsoid, mesh, plane or heightfield",
        )
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Primitive, A::Error> {
        let mut fields = Fields::default();
        while let Some(key) = map.next_key::<String>()? {
            let allowed = match fields.kind {
                Some(k) => key == "type" || k.fields().contains(&key.as_str()),
                None => PRIMITIVE_FIELDS.contains(&key.as_str()),
            };
            let already = fields.has(&key);
            if !allowed || already {
                let message = if already {
                    format!("duplicate field `{key}`")
                } else {
                    unknown_field_message(
                        &key,
                        fields.kind.map_or(PRIMITIVE_FIELDS, PrimitiveKind::fields),
                    )
                };
                map.next_value_seed(Reject(message))?;
                continue;
            }
            fields.read(&key, &mut map)?;
        }
        let kind = fields
            .kind
            .ok_or_else(|| de::Error::missing_field("type"))?;
        // A field given before the tag may not belong to this kind.
        for name in PRIMITIVE_FIELDS.iter().filter(|&&name| name != "type") {
            if fields.has(name) && !kind.fields().contains(name) {
                return Err(de::Error::unknown_field(name, kind.fields()));
            }
        }
        fields.primitive(kind)
    }
}

/// A primitive's fields as read, before its `type` decides which it needs.
#[derive(Default)]
struct Fields {
    kind: Option<PrimitiveKind>,
    size: Option<Vec3>,
    radius: Option<f64>,
    radii: Option<Vec3>,
    height: Option<f64>,
    mesh: MeshDef,
    rows: Option<u32>,
    columns: Option<u32>,
    heights: Option<Vec<f64>>,
}

impl Fields {
    /// Whether field `key` was read.
    fn has(&self, key: &str) -> bool {
        match key {
            "type" => self.kind.is_some(),
            "size" => self.size.is_some(),
            "radius" => self.radius.is_some(),
            "radii" => self.radii.is_some(),
            "height" => self.height.is_some(),
            "vertices" => self.mesh.vertices.is_some(),
            "indices" => self.mesh.indices.is_some(),
            "convex" => self.mesh.convex.is_some(),
            "file" => self.mesh.file.is_some(),
            "scale" => self.mesh.scale.is_some(),
            "rows" => self.rows.is_some(),
            "columns" => self.columns.is_some(),
            "heights" => self.heights.is_some(),
            _ => false,
        }
    }

    /// Reads field `key`'s value from `map`.
    fn read<'de, A: MapAccess<'de>>(&mut self, key: &str, map: &mut A) -> Result<(), A::Error> {
        match key {
            "type" => self.kind = Some(map.next_value()?),
            "size" => self.size = Some(map.next_value()?),
            "radius" => self.radius = Some(map.next_value()?),
            "radii" => self.radii = Some(map.next_value()?),
            "height" => self.height = Some(map.next_value()?),
            "vertices" => self.mesh.vertices = Some(map.next_value()?),
            "indices" => self.mesh.indices = Some(map.next_value()?),
            "convex" => self.mesh.convex = Some(map.next_value()?),
            "file" => self.mesh.file = Some(map.next_value()?),
            "scale" => self.mesh.scale = Some(map.next_value()?),
            "rows" => self.rows = Some(map.next_value()?),
            "columns" => self.columns = Some(map.next_value()?),
            "heights" => self.heights = Some(map.next_value()?),
            _ => {
                map.next_value::<IgnoredAny>()?;
            }
        }
        Ok(())
    }

    /// The primitive of `kind` from its fields, each it needs present.
    fn primitive<E: de::Error>(mut self, kind: PrimitiveKind) -> Result<Primitive, E> {
        let missing = |name: &'static str| E::missing_field(name);
        Ok(match kind {
            PrimitiveKind::Cube => Primitive::Cube {
                size: self.size.ok_or_else(|| missing("size"))?,
            },
            PrimitiveKind::Cylinder => Primitive::Cylinder {
                radius: self.radius.ok_or_else(|| missing("radius"))?,
                height: self.height.ok_or_else(|| missing("height"))?,
            },
            PrimitiveKind::Sphere => Primitive::Sphere {
                radius: self.radius.ok_or_else(|| missing("radius"))?,
            },
            PrimitiveKind::Capsule => Primitive::Capsule {
                radius: self.radius.ok_or_else(|| missing("radius"))?,
                height: self.height.ok_or_else(|| missing("height"))?,
            },
            PrimitiveKind::Ellipsoid => Primitive::Ellipsoid {
                radii: self.radii.ok_or_else(|| missing("radii"))?,
            },
            PrimitiveKind::Mesh => {
                if self.mesh.vertices.is_none() && self.mesh.file.is_none() {
                    return Err(E::custom(
                        "a mesh needs `vertices` (and `indices`) or a `file` of the assets",
                    ));
                }
                Primitive::Mesh(self.mesh)
            }
            PrimitiveKind::Plane => Primitive::Plane,
            PrimitiveKind::Heightfield => Primitive::Heightfield(HeightfieldDef {
                rows: self.rows,
                columns: self.columns,
                size: self.size.ok_or_else(|| missing("size"))?,
                heights: self.heights,
                file: self.mesh.file.take(),
            }),
        })
    }
}
