//! Reading what older servers send, and the typed enums beside the strings: a
//! `BatchInfo`'s flat fields (before `BatchInfo.env`), and a joint's type or a DOF's unit
//! named only by its string (before `JointInfo.kind`, `DofLimit.dof_unit`).

use gymfleet_proto::v1 as pb;
use gymfleet_proto::v1::{DofUnit, JointType, TerminationReason};

/// A wire termination reason as the enum; `None` for none (or one this build does not
/// know).
pub(crate) fn typed_termination(raw: i32) -> Option<TerminationReason> {
    TerminationReason::try_from(raw)
        .ok()
        .filter(|t| *t != TerminationReason::Unspecified)
}

/// A wire enum value, or (unset) the value its string `name` names.
pub(super) fn typed_or_named<E>(raw: i32, name: &str, prefix: &str) -> E
where
    E: TryFrom<i32> + Default + FromStrName + PartialEq,
{
    match E::try_from(raw) {
        Ok(value) if value != E::default() => value,
        _ => E::from_name(&format!("{prefix}{}", name.to_ascii_uppercase())).unwrap_or_default(),
    }
}

/// prost's `from_str_name`, for [`typed_or_named`].
pub(super) trait FromStrName: Sized {
    fn from_name(name: &str) -> Option<Self>;
}

impl FromStrName for JointType {
    fn from_name(name: &str) -> Option<Self> {
        JointType::from_str_name(name)
    }
}

impl FromStrName for DofUnit {
    fn from_name(name: &str) -> Option<Self> {
        DofUnit::from_str_name(name)
    }
}

/// A `BatchInfo`'s deprecated flat fields as the `EnvInfo` they repeat.
#[allow(deprecated)]
pub(super) fn flat_env_info(i: pb::BatchInfo) -> pb::EnvInfo {
    pb::EnvInfo {
        env_id: String::new(),
        num_joints: i.num_joints,
        action_dim: i.action_dim,
        observation_dim: i.observation_dim,
        end_effector_ids: i.end_effector_ids,
        dt: i.dt,
        substeps: i.substeps,
        max_steps: i.max_steps,
        joints: i.joints,
        observation_layout: i.observation_layout,
        units: i.units,
        term_names: i.term_names,
        free_bodies: i.free_bodies,
        mocap_bodies: i.mocap_bodies,
        moving_mass: i.moving_mass,
        actuators: i.actuators,
        keyframes: i.keyframes,
        heightfields: i.heightfields,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unset_enums_are_read_from_their_strings() {
        assert_eq!(
            typed_or_named::<JointType>(0, "ball", "JOINT_TYPE_"),
            JointType::Ball
        );
        assert_eq!(
            typed_or_named::<JointType>(JointType::Prismatic as i32, "revolute", "JOINT_TYPE_"),
            JointType::Prismatic,
            "a set enum wins"
        );
        assert_eq!(typed_or_named::<DofUnit>(0, "mm", "DOF_UNIT_"), DofUnit::Mm);
        assert_eq!(
            typed_or_named::<DofUnit>(0, "furlongs", "DOF_UNIT_"),
            DofUnit::Unspecified
        );
        assert_eq!(typed_termination(0), None);
        assert_eq!(
            typed_termination(99),
            None,
            "a reason this build does not know"
        );
        assert_eq!(typed_termination(3), Some(TerminationReason::Fell));
    }

    #[test]
    #[allow(deprecated)]
    fn an_older_servers_flat_batch_info_is_its_env_info() {
        let env = flat_env_info(pb::BatchInfo {
            batch_id: "batch_1".into(),
            n_envs: 4,
            action_dim: 2,
            observation_dim: 11,
            term_names: vec!["reach".into()],
            ..Default::default()
        });
        assert_eq!((env.action_dim, env.observation_dim), (2, 11));
        assert_eq!(env.term_names, ["reach"]);
        assert!(env.env_id.is_empty());
    }
}
