//! What [`crate::RobotEnv::new`] derives from an assembly and a config before it builds
//! the env: the end effectors, the reset noise on the positions, and the env's spec.

use gymfleet_assembly::Assembly;
use gymfleet_physics::RobotWorld;

use crate::config::{EnvConfig, EnvSpec};
use crate::error::{EnvError, Result};
use crate::task::ActiveTask;
use crate::terms::{ActiveTerms, Dist};
use crate::Units;

/// An end effector: its instance, and for a site its point (mm) and axes (Euler angles,
/// radians) in the instance's frame.
pub(crate) type EndEffector = (usize, Option<([f64; 3], [f64; 3])>);

/// The instances' and joints' names, in document order.
pub(crate) fn names(assembly: &Assembly) -> std::sync::Arc<(Vec<String>, Vec<String>)> {
    std::sync::Arc::new((
        assembly.instances.iter().map(|i| i.name.clone()).collect(),
        assembly.joints.iter().map(|j| j.name.clone()).collect(),
    ))
}

/// Each site by name, as an end effector.
pub(crate) fn sites(assembly: &Assembly) -> std::sync::Arc<[(String, EndEffector)]> {
    assembly
        .sites
        .iter()
        .map(|s| (s.name.clone(), (s.instance, Some((s.point, s.rotation)))))
        .collect()
}

/// Each end effector id's instance and, for a site, its point and rotation: an instance
/// by that name, else a site by that name; `site:NAME` is always the site (an MJCF body's
/// origin where a geom has its name).
pub(crate) fn end_effectors(assembly: &Assembly, ids: &[String]) -> Result<Vec<EndEffector>> {
    let site = |name: &str| {
        assembly.site_index(name).map(|k| {
            let site = &assembly.sites[k];
            (site.instance, Some((site.point, site.rotation)))
        })
    };
    ids.iter()
        .enumerate()
        .map(|(index, id)| {
            let found = match id.strip_prefix("site:") {
                Some(name) => site(name),
                None => assembly
                    .instance_index(id)
                    .map(|i| (i, None))
                    .or_else(|| site(id)),
            };
            found.ok_or_else(|| EnvError::UnknownEndEffector {
                index,
                id: gymfleet_assembly::quoted(id),
                known: gymfleet_assembly::quoted_list(
                    &assembly
                        .instances
                        .iter()
                        .map(|i| i.name.as_str())
                        .collect::<Vec<_>>(),
                ),
            })
        })
        .collect()
}

/// The noise a reset draws on the positions: the config's `reset_noise` or the task's,
/// never both.
pub(crate) fn position_noise(
    config: &EnvConfig,
    terms: Option<&ActiveTerms>,
) -> Result<Option<(Dist, Units)>> {
    let mut noise =
        (config.reset_noise > 0.0).then_some((Dist::Uniform(config.reset_noise), Units::Document));
    if let Some(dist) = terms.and_then(|t| t.position_noise) {
        if noise.is_some() {
            return Err(EnvError::BadConfig {
                field: "reset_noise",
                reason: "the task draws the positions (task.terms.reset_noise.position); \
                         set one of the two"
                    .into(),
            });
        }
        noise = Some((dist, config.units));
    }
    Ok(noise)
}

/// The env's spec: its DOFs, observed bodies, observation segments, terms, actuators,
/// keyframes, heightfields and sensors.
pub(crate) fn env_spec(
    assembly: &Assembly,
    config: &EnvConfig,
    world: &RobotWorld,
    task: Option<&ActiveTask>,
) -> EnvSpec {
    let segment = task.and_then(|t| t.observation_name().map(|name| (name, t.observation_dim())));
    let term_names = match &config.task {
        Some(crate::TaskSpec {
            kind: crate::TaskKind::Terms(t),
            ..
        }) => t.terms.iter().map(|t| t.name.clone()).collect(),
        _ => Vec::new(),
    };
    let names = |list: Vec<usize>| -> Vec<String> {
        list.into_iter()
            .map(|i| assembly.instances[i].name.clone())
            .collect()
    };
    let bodies = crate::config::ObservedBodies {
        floating_base: world.has_floating_base(),
        free_bodies: names(assembly.free_bodies()),
        mocap_bodies: names(assembly.mocap_bodies()),
        moving_mass: world.moving_mass(),
    };
    let actuators = crate::config::ActuatorSpec::of(assembly);
    let mut spec = EnvSpec::new(config, world.dofs(), bodies, segment, term_names, actuators);
    spec.keyframes = assembly.keyframes.iter().map(|k| k.name.clone()).collect();
    spec.heightfields = world
        .heightfields()
        .into_iter()
        .map(|(i, rows, columns)| (assembly.instances[i].name.clone(), rows, columns))
        .collect();
    spec.sensors = assembly
        .sensors
        .iter()
        .map(|s| (s.name.clone(), s.kind.as_str(), s.kind.dim()))
        .collect();
    spec
}
