//! Mesh primitives made convex: a document's triangle mesh becomes one convex hull or a
//! V-HACD convex decomposition (parry's, the geometry crate Rapier itself uses), checked
//! and bounded here so that the physics layer only ever builds shapes that exist.

use std::sync::Arc;

use parry3d::math::Vector;
use parry3d::shape::ConvexPolyhedron;
use parry3d::transformation::vhacd::{VHACDParameters, VHACD};

use crate::document::ConvexMode;

/// Most vertices a mesh primitive may have.
pub const MAX_MESH_VERTICES: usize = 65_536;
/// Most triangles a mesh primitive may have.
pub const MAX_MESH_TRIANGLES: usize = 131_072;
/// Most triangles a mesh to decompose may have: V-HACD voxelises every triangle, so this
/// (with the fixed voxel resolution below) bounds a decomposition's time.
pub const MAX_DECOMPOSED_TRIANGLES: usize = 32_768;
/// Most convex parts a decomposition keeps.
pub const MAX_CONVEX_PARTS: u32 = 32;
/// V-HACD's voxel grid resolution (parry's default).
const VOXEL_RESOLUTION: u32 = 64;
/// Latitude rings of the polyhedron an ellipsoid is collided as (twice as many longitudes).
pub const ELLIPSOID_RINGS: usize = 16;

/// One convex polyhedron in the part's frame, m: its hull vertices and outward triangles.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexPiece {
    /// Hull vertices, m.
    pub vertices: Vec<[f64; 3]>,
    /// Hull triangles, indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

/// A mesh primitive made convex: one piece for a hull, several for a decomposition.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexParts {
    /// The convex pieces, together the part's shape.
    pub pieces: Vec<ConvexPiece>,
}

impl ConvexParts {
    /// The convex shapes of a mesh given in m (`indices` already checked to be in range).
    pub(crate) fn new(
        vertices: &[[f64; 3]],
        indices: Option<&[[u32; 3]]>,
        mode: ConvexMode,
    ) -> Result<Arc<ConvexParts>, String> {
        let points: Vec<Vector> = vertices
            .iter()
            .map(|v| Vector::new(v[0] as f32, v[1] as f32, v[2] as f32))
            .collect();
        let hulls = match (mode, indices) {
            (ConvexMode::Hull, _) => vec![points],
            (ConvexMode::Decomposition, None) => {
                return Err("a decomposition needs the mesh's `indices` (its triangles)".into())
            }
            (ConvexMode::Decomposition, Some(indices)) => {
                if indices.len() > MAX_DECOMPOSED_TRIANGLES {
                    return Err(format!(
                        "a mesh to decompose may have at most {MAX_DECOMPOSED_TRIANGLES} triangles, got {}; use \"convex\": \"hull\" or simplify the mesh",
                        indices.len()
                    ));
                }
                let params = VHACDParameters {
                    resolution: VOXEL_RESOLUTION,
                    max_convex_hulls: MAX_CONVEX_PARTS,
                    ..VHACDParameters::default()
                };
                VHACD::decompose(&params, &points, indices, false)
                    .compute_convex_hulls(params.convex_hull_downsampling)
                    .into_iter()
                    .map(|(vertices, _)| vertices)
                    .collect()
            }
        };
        let pieces: Vec<ConvexPiece> = hulls.iter().filter_map(|h| hull(h)).collect();
        if pieces.is_empty() {
            return Err(match mode {
                ConvexMode::Hull => {
                    "the vertices span no volume (fewer than 4 of them, or all on one plane)".into()
                }
                ConvexMode::Decomposition => {
                    "the decomposition found no volume: is the mesh closed?".into()
                }
            });
        }
        Ok(Arc::new(ConvexParts { pieces }))
    }

    /// The convex polyhedron an ellipsoid of semi-axes `radii` (m) is collided as: a
    /// latitude–longitude grid of [`ELLIPSOID_RINGS`] × 2·[`ELLIPSOID_RINGS`] points on its
    /// surface, scaled so that the hull has the ellipsoid's volume (its vertices lie up to
    /// about 1 % outside the surface, its faces' middles inside it).
    pub(crate) fn ellipsoid(radii: [f64; 3]) -> Result<Arc<ConvexParts>, String> {
        let grid = |scale: f64| -> Vec<Vector> {
            let (rings, sectors) = (ELLIPSOID_RINGS, 2 * ELLIPSOID_RINGS);
            let mut points = vec![
                Vector::new(0.0, 0.0, (radii[2] * scale) as f32),
                Vector::new(0.0, 0.0, (-radii[2] * scale) as f32),
            ];
            for i in 1..rings {
                let theta = std::f64::consts::PI * i as f64 / rings as f64;
                for j in 0..sectors {
                    let phi = std::f64::consts::TAU * j as f64 / sectors as f64;
                    points.push(Vector::new(
                        (radii[0] * scale * theta.sin() * phi.cos()) as f32,
                        (radii[1] * scale * theta.sin() * phi.sin()) as f32,
                        (radii[2] * scale * theta.cos()) as f32,
                    ));
                }
            }
            points
        };
        let exact = 4.0 / 3.0 * std::f64::consts::PI * radii[0] * radii[1] * radii[2];
        let inscribed = hull(&grid(1.0)).ok_or("the ellipsoid spans no volume")?;
        let (volume, _) = inscribed.volume_and_centroid();
        let scale = (exact / volume).cbrt();
        let piece = hull(&grid(scale)).ok_or("the ellipsoid spans no volume")?;
        Ok(Arc::new(ConvexParts {
            pieces: vec![piece],
        }))
    }

    /// Total volume, m³.
    pub fn volume(&self) -> f64 {
        self.pieces.iter().map(|p| p.volume_and_centroid().0).sum()
    }

    /// The volume-weighted centroid, m.
    pub fn centroid(&self) -> [f64; 3] {
        let mut sum = [0.0; 3];
        let mut volume = 0.0;
        for piece in &self.pieces {
            let (v, c) = piece.volume_and_centroid();
            volume += v;
            for k in 0..3 {
                sum[k] += v * c[k];
            }
        }
        sum.map(|s| s / volume)
    }

    /// The smallest side of any piece's axis-aligned box, m.
    pub fn min_extent(&self) -> f64 {
        self.pieces
            .iter()
            .map(|p| {
                let mut lo = [f64::INFINITY; 3];
                let mut hi = [f64::NEG_INFINITY; 3];
                for v in &p.vertices {
                    for k in 0..3 {
                        lo[k] = lo[k].min(v[k]);
                        hi[k] = hi[k].max(v[k]);
                    }
                }
                (0..3).map(|k| hi[k] - lo[k]).fold(f64::INFINITY, f64::min)
            })
            .fold(f64::INFINITY, f64::min)
    }
}

impl ConvexPiece {
    /// Volume (m³) and centroid (m), by tetrahedra from an interior point: right for any
    /// convex polyhedron whatever its triangles' winding.
    fn volume_and_centroid(&self) -> (f64, [f64; 3]) {
        let n = self.vertices.len() as f64;
        let mut inner = [0.0; 3];
        for v in &self.vertices {
            for k in 0..3 {
                inner[k] += v[k] / n;
            }
        }
        let mut volume = 0.0;
        let mut moment = [0.0; 3];
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.vertices[i as usize]);
            let d = |p: [f64; 3]| [p[0] - inner[0], p[1] - inner[1], p[2] - inner[2]];
            let (a1, b1, c1) = (d(a), d(b), d(c));
            let det = a1[0] * (b1[1] * c1[2] - b1[2] * c1[1])
                - a1[1] * (b1[0] * c1[2] - b1[2] * c1[0])
                + a1[2] * (b1[0] * c1[1] - b1[1] * c1[0]);
            let v = det.abs() / 6.0;
            volume += v;
            for k in 0..3 {
                moment[k] += v * (inner[k] + a[k] + b[k] + c[k]) / 4.0;
            }
        }
        (volume, moment.map(|m| m / volume))
    }
}

/// The convex hull of `points` as a piece, if it has a volume parry can build a
/// polyhedron from (what the physics layer then builds, exactly so).
fn hull(points: &[Vector]) -> Option<ConvexPiece> {
    let (vertices, triangles) = parry3d::transformation::try_convex_hull(points).ok()?;
    ConvexPolyhedron::from_convex_mesh(vertices.clone(), &triangles)?;
    let piece = ConvexPiece {
        vertices: vertices
            .iter()
            .map(|v| [f64::from(v.x), f64::from(v.y), f64::from(v.z)])
            .collect(),
        triangles,
    };
    (piece.volume_and_centroid().0 > 0.0).then_some(piece)
}
