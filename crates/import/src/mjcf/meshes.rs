//! `<asset><mesh>` and mesh geoms. A mesh geom becomes a `mesh` primitive that names its
//! file (under `compiler meshdir`), read from the request's assets after the conversion
//! ([`crate::inline_mesh_files`]) and simulated as its convex hull, as URDF meshes are;
//! a mesh given inline (`vertex`) keeps its vertices. The vertices stay in the geom's frame
//! as the file has them (MuJoCo re-centres a mesh on its inertial frame and moves the geom
//! by the same offset, so the mesh ends up where the file puts it).

use super::*;

/// One `<asset><mesh>`: where its vertices come from and its scale.
#[derive(Debug, Clone)]
pub(super) struct MeshAsset {
    source: MeshSource,
    scale: [f64; 3],
}

#[derive(Debug, Clone)]
enum MeshSource {
    /// A file, by its path under `meshdir`.
    File(String),
    /// `vertex`: the vertices in metres.
    Inline(Vec<[f64; 3]>),
}

impl<'a, 'i> Converter<'a, 'i> {
    /// A `file` attribute's path in the assets: under `meshdir` (else `assetdir`), from the
    /// model's folder (meshes and heightfields).
    pub(super) fn asset_file(&self, node: Node<'a, 'i>, file: &str) -> Result<String> {
        let path = match self.mesh_dir.as_deref() {
            Some(dir) if !dir.is_empty() && !file.starts_with('/') => {
                format!("{}/{file}", dir.trim_end_matches('/'))
            }
            _ => file.to_string(),
        };
        crate::asset_path(&self.folder, &path).map_err(|reason| self.bad(node, "file", reason))
    }

    /// `<asset><mesh>`: named by `name`, else by its file's name without the extension.
    pub(super) fn mesh_asset(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for attr in [
            "refpos",
            "refquat",
            "face",
            "normal",
            "texcoord",
            "content_type",
        ] {
            if node.attribute(attr).is_some() {
                return Err(self.unsupported(node, format!("{attr} is not supported yet")));
            }
        }
        let scale = self
            .exactly::<3>(node, node.attribute("class"), "scale")?
            .unwrap_or([1.0; 3]);
        if let Some(v) = scale.iter().find(|v| !(v.is_finite() && **v != 0.0)) {
            return Err(self.bad(node, "scale", format!("expected non-zero factors, got {v}")));
        }
        let (source, stem) = match (node.attribute("file"), node.attribute("vertex")) {
            (Some(file), None) => {
                let file = if self.strip_path {
                    file.rsplit(['/', '\\']).next().unwrap_or(file)
                } else {
                    file
                };
                let stem = file.rsplit(['/', '\\']).next().unwrap_or(file);
                let stem = stem.rsplit_once('.').map_or(stem, |(s, _)| s).to_string();
                (MeshSource::File(self.asset_file(node, file)?), Some(stem))
            }
            (None, Some(_)) => {
                let values = self.numbers(node, None, "vertex")?.unwrap_or_default();
                if values.len() < 12 || values.len() % 3 != 0 {
                    return Err(self.bad(
                        node,
                        "vertex",
                        format!(
                            "expected at least 4 points (x y z each), got {} numbers",
                            values.len()
                        ),
                    ));
                }
                let points = values.chunks(3).map(|p| [p[0], p[1], p[2]]).collect();
                (MeshSource::Inline(points), None)
            }
            (Some(_), Some(_)) => {
                return Err(self.bad(node, "vertex", "expected one of file or vertex".into()))
            }
            (None, None) => {
                return Err(self.bad(node, "file", "missing (or vertex)".into()));
            }
        };
        let Some(name) = node.attribute("name").map(str::to_string).or(stem) else {
            return Err(self.bad(
                node,
                "name",
                "missing (a mesh given by vertex needs one)".into(),
            ));
        };
        for attr in ["smoothnormal", "maxhullvert", "inertia"] {
            if node.attribute(attr).is_some() {
                self.warn(
                    node,
                    format!("{attr} ignored (meshes are simulated as their hull)"),
                );
            }
        }
        if self
            .meshes
            .insert(name.clone(), MeshAsset { source, scale })
            .is_some()
        {
            return Err(self.bad(
                node,
                "name",
                format!("a mesh named {name:?} is defined twice"),
            ));
        }
        Ok(())
    }

    /// A mesh geom's primitive, in the geom's frame (mm).
    pub(super) fn mesh_primitive(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
    ) -> Result<Primitive> {
        let name = self.attr(node, class, "mesh").ok_or_else(|| {
            self.bad(
                node,
                "mesh",
                "missing: a mesh geom names an <asset><mesh>".into(),
            )
        })?;
        let Some(mesh) = self.meshes.get(name) else {
            let mut known: Vec<&String> = self.meshes.keys().collect();
            known.sort();
            return Err(self.bad(
                node,
                "mesh",
                format!(
                    "no <asset><mesh> is named {name:?} (there are {}: {})",
                    known.len(),
                    known
                        .iter()
                        .take(8)
                        .map(|k| format!("{k:?}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        };
        let s = mesh.scale;
        Ok(match &mesh.source {
            MeshSource::File(file) => Primitive::Mesh(MeshDef {
                file: Some(file.clone()),
                convex: Some(gymfleet_assembly::ConvexMode::Hull),
                scale: Some(vec3(DVec3::from_array(s) * MM)),
                ..MeshDef::default()
            }),
            MeshSource::Inline(points) => {
                let vertices: Vec<[f64; 3]> = points
                    .iter()
                    .map(|p| [p[0] * s[0] * MM, p[1] * s[1] * MM, p[2] * s[2] * MM])
                    .collect();
                Primitive::Mesh(MeshDef {
                    vertices: Some(vertices),
                    ..MeshDef::default()
                })
            }
        })
    }
}
