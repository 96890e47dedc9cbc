//! Heightfields replaced at run time ([`crate::EnvSpec::heightfields`]), as dm_control's
//! tasks write MuJoCo's `hfield_data` at an episode's start: by name, `rows × columns`
//! heights in [0, 1], row 0 at −y. The new terrain stays through resets and travels in
//! saved states.

use gymfleet_assembly::{quoted, quoted_list};

use crate::env::RobotEnv;
use crate::error::{EnvError, Result};

impl RobotEnv {
    /// The position of heightfield `name` among [`crate::EnvSpec::heightfields`].
    pub fn heightfield_index(&self, name: &str) -> Result<usize> {
        let fields = &self.spec().heightfields;
        fields
            .iter()
            .position(|(n, ..)| n == name)
            .ok_or_else(|| EnvError::UnknownHeightfield {
                name: quoted(name),
                known: if fields.is_empty() {
                    "none: the document has no heightfield".to_string()
                } else {
                    quoted_list(&fields.iter().map(|(n, ..)| n.as_str()).collect::<Vec<_>>())
                },
            })
    }

    /// Checks heights for heightfield `name`, changing nothing: its index.
    pub fn check_heightfield(&self, name: &str, heights: &[f32]) -> Result<usize> {
        let k = self.heightfield_index(name)?;
        let (_, rows, columns) = self.spec().heightfields[k];
        let bad = |reason: String| EnvError::BadHeights {
            name: quoted(name),
            reason,
        };
        if heights.len() != rows * columns {
            return Err(bad(format!(
                "expected rows × columns = {rows} × {columns} = {} heights, got {}",
                rows * columns,
                heights.len()
            )));
        }
        if let Some((i, h)) = heights
            .iter()
            .enumerate()
            .find(|(_, h)| !(h.is_finite() && (0.0..=1.0).contains(*h)))
        {
            return Err(bad(format!("heights[{i}] is {h}; heights are in [0, 1]")));
        }
        Ok(k)
    }

    /// Replaces heightfield `name`'s heights (see the module documentation). A bad name,
    /// count or height is refused and changes nothing.
    pub fn set_heightfield(&mut self, name: &str, heights: &[f32]) -> Result<()> {
        let k = self.check_heightfield(name, heights)?;
        let heights: Vec<f64> = heights.iter().map(|&h| f64::from(h)).collect();
        self.world.set_heightfield(k, &heights)?;
        Ok(())
    }
}
