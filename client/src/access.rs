//! MuJoCo-shaped state access on an [`Env`]: [`Env::set_joint_state`] (MuJoCo's
//! `set_state(qpos, qvel)`) and [`Env::bodies`] (every instance's and site's state).

use gymfleet_proto::v1 as pb;

use crate::types::Observation;
use crate::{Env, Result};

/// Every instance's and site's state, as the server read it ([`Env::bodies`]). The
/// per-instance fields follow [`Bodies::instances`] (document order) and the per-site ones
/// [`Bodies::sites`]; lengths and positions are in the env's units, the c-frame
/// quantities (MuJoCo's `cinert`, `cvel`, `cfrc_ext`) SI about [`Bodies::about`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Bodies {
    /// The instances' names.
    pub instances: Vec<String>,
    /// Each instance's own mass, kg (as randomised this episode).
    pub masses: Vec<f64>,
    /// 3 per instance: its centre of mass, world.
    pub centers_of_mass: Vec<f64>,
    /// 10 per instance: MuJoCo's `cinert` about [`Bodies::about`] (a group's is the sum).
    pub inertias: Vec<f64>,
    /// 6 per instance: MuJoCo's `cvel` at [`Bodies::about`] (angular, then linear).
    pub velocities: Vec<f64>,
    /// 6 per instance: the last step's contact wrench about [`Bodies::about`] (torque,
    /// then force; MuJoCo's `cfrc_ext`).
    pub contact_wrenches: Vec<f64>,
    /// The robot's centre of mass, m: the point the c-frame quantities are taken about.
    pub about: [f64; 3],
    /// The document's sites' names (an MJCF body's origin is one, by the body's name).
    pub sites: Vec<String>,
    /// 7 per site: position, then `[qw, qx, qy, qz]`.
    pub site_poses: Vec<f64>,
    /// One per DOF: the generalized force the command applies (MuJoCo's `qfrc_actuator`).
    pub actuator_forces: Vec<f64>,
    /// The document's sensors' names, in order.
    pub sensors: Vec<String>,
    /// One per sensor: its type (MJCF's element name).
    pub sensor_types: Vec<String>,
    /// One per sensor: the floats it reports.
    pub sensor_dims: Vec<u32>,
    /// Every sensor's reading, SI, in order (MuJoCo's `sensordata`).
    pub sensor_data: Vec<f64>,
}

impl From<pb::Bodies> for Bodies {
    fn from(b: pb::Bodies) -> Self {
        let mut about = [0.0; 3];
        for (slot, value) in about.iter_mut().zip(&b.about) {
            *slot = *value;
        }
        Bodies {
            instances: b.instances,
            masses: b.masses,
            centers_of_mass: b.centers_of_mass,
            inertias: b.inertias,
            velocities: b.velocities,
            contact_wrenches: b.contact_wrenches,
            about,
            sites: b.sites,
            site_poses: b.site_poses,
            actuator_forces: b.actuator_forces,
            sensors: b.sensors,
            sensor_types: b.sensor_types,
            sensor_dims: b.sensor_dims,
            sensor_data: b.sensor_data,
        }
    }
}

impl Env {
    /// Sets the env's joint state from values, as MuJoCo's `set_state(qpos, qvel)` does:
    /// one position and one velocity per DOF as the observation has them, and with a
    /// floating base its 13 floats (the observation's `base_pose` then `base_velocity`;
    /// empty without one). The episode goes on. Returns the observation there and the
    /// server's warnings: a position past a hard limit set at the limit, a joint on a
    /// kinematic loop kept. A wrong count or a non-finite value is
    /// [`crate::ClientError::InvalidArgument`] and changes nothing.
    pub async fn set_joint_state(
        &self,
        positions: &[f64],
        velocities: &[f64],
        base: &[f64],
    ) -> Result<(Observation, Vec<String>)> {
        let request = pb::SetJointStateRequest {
            env_id: self.id().to_string(),
            joint_positions: positions.to_vec(),
            joint_velocities: velocities.to_vec(),
            base_state: base.to_vec(),
        };
        let result = self
            .client
            .rpc()
            .set_joint_state(request)
            .await?
            .into_inner();
        let observation = result.observation.unwrap_or_default().try_into()?;
        Ok((observation, result.warnings))
    }

    /// Every instance's and site's state now (reads only).
    pub async fn bodies(&self) -> Result<Bodies> {
        let bodies = self.client.rpc().get_bodies(self.env_ref()).await?;
        Ok(bodies.into_inner().into())
    }
}
