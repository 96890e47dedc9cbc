//! Heightfields *(ext)*: terrain as MuJoCo's `hfield` has it, a grid of elevations in
//! [0, 1] scaled by the top elevation, checked here and replaceable at run time
//! ([`Heightfield::with_heights`]).

use crate::document::HeightfieldDef;
use crate::error::Issue;

/// Most grid points along either side of one heightfield.
pub const MAX_HEIGHTFIELD_SIDE: u32 = 1024;
/// Most grid points of one heightfield.
pub const MAX_HEIGHTFIELD_POINTS: usize = 1 << 20;

/// A validated heightfield, SI.
#[derive(Debug, Clone, PartialEq)]
pub struct Heightfield {
    /// Grid rows (along y) and columns (along x), each at least 2.
    pub rows: usize,
    /// Grid columns.
    pub columns: usize,
    /// Half-extents along x and y, m.
    pub half_extents: [f64; 2],
    /// The elevation a height of 1 reaches, m (≥ 0).
    pub elevation: f64,
    /// `rows × columns` heights in [0, 1], row 0 at `y = −half_extents[1]`, each row along
    /// x from `−half_extents[0]`.
    pub heights: Vec<f64>,
}

impl Heightfield {
    /// The same heightfield with other heights, checked as a document's are: `Err` names
    /// the first problem.
    pub fn with_heights(&self, heights: &[f64]) -> Result<Heightfield, String> {
        check_heights(heights, self.rows * self.columns)?;
        Ok(Heightfield {
            heights: heights.to_vec(),
            ..self.clone()
        })
    }

    /// The height (m above the part's XY plane) at grid point (`row`, `column`).
    pub fn height_at(&self, row: usize, column: usize) -> f64 {
        self.heights[row * self.columns + column] * self.elevation
    }
}

fn check_heights(heights: &[f64], points: usize) -> Result<(), String> {
    if heights.len() != points {
        return Err(format!(
            "expected rows × columns = {points} heights, got {}",
            heights.len()
        ));
    }
    if let Some((k, h)) = heights
        .iter()
        .enumerate()
        .find(|(_, h)| !(h.is_finite() && (0.0..=1.0).contains(*h)))
    {
        return Err(format!("height {k} is {h}; heights are in [0, 1]"));
    }
    Ok(())
}

/// A document's heightfield primitive, checked; every problem is an issue.
pub(crate) fn heightfield(
    path: &str,
    def: &HeightfieldDef,
    issues: &mut Vec<Issue>,
) -> Option<Heightfield> {
    let before = issues.len();
    if let Some(file) = &def.file {
        issues.push(Issue::new(
            format!("{path}.file"),
            format!("the heightfield's file {file:?} is read from the request's assets; none came with it"),
        ));
        return None;
    }
    let (Some(rows), Some(columns)) = (def.rows, def.columns) else {
        issues.push(Issue::new(
            format!("{path}.rows"),
            "missing: a heightfield needs rows and columns (or a file of the assets)",
        ));
        return None;
    };
    let mut length = |at: String, mm: f64, positive: bool| {
        let ok = mm.is_finite() && if positive { mm > 0.0 } else { mm >= 0.0 };
        if !ok {
            let what = if positive {
                "a positive"
            } else {
                "a non-negative"
            };
            issues.push(Issue::new(
                at,
                format!("expected {what} length in mm, got {mm}"),
            ));
        }
        mm / 1000.0
    };
    let half_x = length(format!("{path}.size.x"), def.size.x, true);
    let half_y = length(format!("{path}.size.y"), def.size.y, true);
    let elevation = length(format!("{path}.size.z"), def.size.z, false);
    for (name, n) in [("rows", rows), ("columns", columns)] {
        if !(2..=MAX_HEIGHTFIELD_SIDE).contains(&n) {
            issues.push(Issue::new(
                format!("{path}.{name}"),
                format!("expected 2 to {MAX_HEIGHTFIELD_SIDE} {name}, got {n}"),
            ));
        }
    }
    let points = rows as usize * columns as usize;
    if points > MAX_HEIGHTFIELD_POINTS {
        issues.push(Issue::new(
            format!("{path}.rows"),
            format!("expected at most {MAX_HEIGHTFIELD_POINTS} grid points, got {points}"),
        ));
    }
    if issues.len() != before {
        return None;
    }
    let heights = def.heights.clone().unwrap_or_else(|| vec![0.0; points]);
    if let Err(message) = check_heights(&heights, points) {
        issues.push(Issue::new(format!("{path}.heights"), message));
        return None;
    }
    Some(Heightfield {
        rows: rows as usize,
        columns: columns as usize,
        half_extents: [half_x, half_y],
        elevation,
        heights,
    })
}
