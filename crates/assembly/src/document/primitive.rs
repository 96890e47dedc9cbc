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
        let mut kind: Option<PrimitiveKind> = None;
        let mut size: Option<Vec3> = None;
        let mut radius: Option<f64> = None;
        let mut radii: Option<Vec3> = None;
        let mut height: Option<f64> = None;
        let mut mesh = MeshDef::default();
        let mut rows: Option<u32> = None;
        let mut columns: Option<u32> = None;
        let mut heights: Option<Vec<f64>> = None;
        while let Some(key) = map.next_key::<String>()? {
            let allowed = match kind {
                Some(k) => key == "type" || k.fields().contains(&key.as_str()),
                None => PRIMITIVE_FIELDS.contains(&key.as_str()),
            };
            let already = match key.as_str() {
                "type" => kind.is_some(),
                "size" => size.is_some(),
                "radius" => radius.is_some(),
                "radii" => radii.is_some(),
                "height" => height.is_some(),
                "vertices" => mesh.vertices.is_some(),
                "indices" => mesh.indices.is_some(),
                "convex" => mesh.convex.is_some(),
                "file" => mesh.file.is_some(),
                "scale" => mesh.scale.is_some(),
                "rows" => rows.is_some(),
                "columns" => columns.is_some(),
                "heights" => heights.is_some(),
                _ => false,
            };
            if !allowed || already {
                let message = if already {
                    format!("duplicate field `{key}`")
                } else {
                    unknown_field_message(
                        &key,
                        kind.map_or(PRIMITIVE_FIELDS, PrimitiveKind::fields),
                    )
                };
                map.next_value_seed(Reject(message))?;
                continue;
            }
            match key.as_str() {
                "type" => kind = Some(map.next_value()?),
                "size" => size = Some(map.next_value()?),
                "radius" => radius = Some(map.next_value()?),
                "radii" => radii = Some(map.next_value()?),
                "height" => height = Some(map.next_value()?),
                "vertices" => mesh.vertices = Some(map.next_value()?),
                "indices" => mesh.indices = Some(map.next_value()?),
                "convex" => mesh.convex = Some(map.next_value()?),
                "file" => mesh.file = Some(map.next_value()?),
                "scale" => mesh.scale = Some(map.next_value()?),
                "rows" => rows = Some(map.next_value()?),
                "columns" => columns = Some(map.next_value()?),
                "heights" => heights = Some(map.next_value()?),
                _ => {
                    map.next_value::<IgnoredAny>()?;
                }
            }
        }
        let kind = kind.ok_or_else(|| de::Error::missing_field("type"))?;
        // A field given before the tag may not belong to this kind.
        for (name, present) in [
            ("size", size.is_some()),
            ("radius", radius.is_some()),
            ("radii", radii.is_some()),
            ("height", height.is_some()),
            ("vertices", mesh.vertices.is_some()),
            ("indices", mesh.indices.is_some()),
            ("convex", mesh.convex.is_some()),
            ("file", mesh.file.is_some()),
            ("scale", mesh.scale.is_some()),
            ("rows", rows.is_some()),
            ("columns", columns.is_some()),
            ("heights", heights.is_some()),
        ] {
            if present && !kind.fields().contains(&name) {
                return Err(de::Error::unknown_field(name, kind.fields()));
            }
        }
        Ok(match kind {
            PrimitiveKind::Cube => Primitive::Cube {
                size: size.ok_or_else(|| de::Error::missing_field("size"))?,
            },
            PrimitiveKind::Cylinder => Primitive::Cylinder {
                radius: radius.ok_or_else(|| de::Error::missing_field("radius"))?,
                height: height.ok_or_else(|| de::Error::missing_field("height"))?,
            },
            PrimitiveKind::Sphere => Primitive::Sphere {
                radius: radius.ok_or_else(|| de::Error::missing_field("radius"))?,
            },
            PrimitiveKind::Capsule => Primitive::Capsule {
                radius: radius.ok_or_else(|| de::Error::missing_field("radius"))?,
                height: height.ok_or_else(|| de::Error::missing_field("height"))?,
            },
            PrimitiveKind::Ellipsoid => Primitive::Ellipsoid {
                radii: radii.ok_or_else(|| de::Error::missing_field("radii"))?,
            },
            PrimitiveKind::Mesh => {
                if mesh.vertices.is_none() && mesh.file.is_none() {
                    return Err(de::Error::custom(
                        "a mesh needs `vertices` (and `indices`) or a `file` of the assets",
                    ));
                }
                Primitive::Mesh(mesh)
            }
            PrimitiveKind::Plane => Primitive::Plane,
            PrimitiveKind::Heightfield => Primitive::Heightfield(HeightfieldDef {
                rows,
                columns,
                size: size.ok_or_else(|| de::Error::missing_field("size"))?,
                heights,
                file: mesh.file.take(),
            }),
        })
    }
}
