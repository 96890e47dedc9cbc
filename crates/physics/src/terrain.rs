//! Heightfields whose heights change at run time, as dm_control's tasks write MuJoCo's
//! `hfield_data` at an episode's start (quadruped's escape). A replaced terrain stays
//! through resets, as MuJoCo's model data does (it is the world's initial copy's too), and
//! travels in the dynamic state, so that a saved state rebuilds it.

use std::sync::Arc;

use gymfleet_assembly::{Assembly, Heightfield, Shape};

use crate::colliders::heightfield_shape;
use crate::error::{PhysicsError, Result};
use crate::world::{RobotWorld, TerrainSlot};

/// The assembly's heightfield instances, in document order.
pub(crate) fn terrain_slots(assembly: &Assembly) -> Vec<TerrainSlot> {
    assembly
        .instances
        .iter()
        .enumerate()
        .filter_map(|(instance, i)| match &i.shape {
            Shape::Heightfield(field) => Some(TerrainSlot {
                instance,
                field: field.clone(),
                document: field.clone(),
            }),
            _ => None,
        })
        .collect()
}

impl RobotWorld {
    /// The heightfields: each one's instance (document order) and grid (rows, columns).
    pub fn heightfields(&self) -> Vec<(usize, usize, usize)> {
        self.terrains
            .iter()
            .map(|t| (t.instance, t.field.rows, t.field.columns))
            .collect()
    }

    /// Replaces heightfield `k`'s heights (`rows × columns` values in [0, 1], row 0 at
    /// −y, as its document's): now and at every reset after. A wrong count or value is
    /// refused and changes nothing.
    ///
    /// # Panics
    ///
    /// If `k` is not a heightfield's index in [`RobotWorld::heightfields`].
    pub fn set_heightfield(&mut self, k: usize, heights: &[f64]) -> Result<()> {
        let field = self.terrains[k]
            .field
            .with_heights(heights)
            .map_err(|reason| PhysicsError::BadOption {
                field: "heights",
                reason,
            })?;
        self.put_terrain(k, Arc::new(field));
        Ok(())
    }

    /// Heightfield `k` with `field`'s heights, in the live sets and the initial copy.
    fn put_terrain(&mut self, k: usize, field: Arc<Heightfield>) {
        let slot = &mut self.terrains[k];
        slot.field = field;
        let shape = heightfield_shape(&slot.field);
        let handle = self.colliders[slot.instance];
        if let Some(co) = self.live.colliders.get_mut(handle) {
            co.set_shape(shape.clone());
        }
        if let Some(co) = Arc::make_mut(&mut self.initial).colliders.get_mut(handle) {
            co.set_shape(shape);
        }
    }

    /// The heights of every replaced heightfield (`None`: the document's), for a saved
    /// state.
    pub(crate) fn terrain_state(&self) -> Vec<Option<Vec<f32>>> {
        self.terrains
            .iter()
            .map(|t| {
                (t.field.heights != t.document.heights)
                    .then(|| t.field.heights.iter().map(|&h| h as f32).collect())
            })
            .collect()
    }

    /// A saved state's heightfields, checked against the document's (nothing changes).
    pub(crate) fn saved_terrains(
        &self,
        terrains: &[Option<Vec<f32>>],
    ) -> Result<Vec<Arc<Heightfield>>> {
        if terrains.len() != self.terrains.len() {
            return Err(PhysicsError::BadState {
                path: "world.terrains".into(),
                reason: format!(
                    "expected {} heightfields, got {}",
                    self.terrains.len(),
                    terrains.len()
                ),
            });
        }
        self.terrains
            .iter()
            .zip(terrains)
            .enumerate()
            .map(|(k, (slot, heights))| match heights {
                None => Ok(slot.document.clone()),
                Some(h) => {
                    let h: Vec<f64> = h.iter().map(|&v| f64::from(v)).collect();
                    slot.document
                        .with_heights(&h)
                        .map(Arc::new)
                        .map_err(|reason| PhysicsError::BadState {
                            path: format!("world.terrains[{k}]"),
                            reason,
                        })
                }
            })
            .collect()
    }

    /// Puts a saved state's heightfields back (checked with
    /// [`RobotWorld::saved_terrains`] first).
    pub(crate) fn restore_terrains(&mut self, fields: Vec<Arc<Heightfield>>) {
        for (k, field) in fields.into_iter().enumerate() {
            if !Arc::ptr_eq(&field, &self.terrains[k].field) {
                self.put_terrain(k, field);
            }
        }
    }
}
