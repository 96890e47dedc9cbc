//! MuJoCo-shaped state access: setting an env's joint state from values, and reading every
//! instance's and site's state.

use crate::domain::Observed;
use crate::error::Result;
use crate::tenant::Tenant;

use super::Simulation;

/// A joint state to set (`SetJointState`): the observation's layout and units.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct JointState {
    pub(crate) positions: Vec<f64>,
    pub(crate) velocities: Vec<f64>,
    /// A floating base's 13 floats, or none.
    pub(crate) base: Vec<f64>,
}

impl Simulation {
    /// Sets env `id`'s joint state; its observation there and what was not set as given.
    pub(crate) async fn set_joint_state(
        &self,
        tenant: &Tenant,
        id: &str,
        state: JointState,
    ) -> Result<(Observed, Vec<String>)> {
        self.on_env(tenant, id, "SetJointState", move |open| {
            let mut obs = open.observation_buffer();
            let notes = open.env.set_joint_state(
                &state.positions,
                &state.velocities,
                &state.base,
                &mut obs.flat,
            )?;
            open.was_done.fill(false);
            Ok((obs, notes.iter().map(ToString::to_string).collect()))
        })
        .await
    }

    /// Env `id`'s instances and sites now.
    pub(crate) async fn bodies(&self, tenant: &Tenant, id: &str) -> Result<gymfleet_env::Bodies> {
        self.on_env(tenant, id, "GetBodies", |open| Ok(open.env.bodies()))
            .await
    }
}
