//! The handles' descriptions as Python dicts: what `EnvInfo`/`BatchInfo` say, with the
//! joints' limits and effort clamps from which the package builds its spaces.

use gymfleet_client::{ActuatorInfo, BatchInfo, EnvInfo, JointInfo};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

fn joint<'py>(py: Python<'py>, j: &JointInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &j.name)?;
    d.set_item("type", &j.joint_type)?;
    d.set_item("dof", j.dof)?;
    d.set_item("parent", &j.parent)?;
    d.set_item("child", &j.child)?;
    d.set_item("max_effort", j.max_effort)?;
    d.set_item("actuated", j.actuated)?;
    d.set_item("gear", j.gear)?;
    d.set_item("reference", j.reference)?;
    d.set_item("action_bounds", j.action_bounds.clone())?;
    let limits = j
        .limits
        .iter()
        .map(|l| {
            let limit = PyDict::new(py);
            limit.set_item("unit", &l.unit)?;
            limit.set_item("min", l.min)?;
            limit.set_item("max", l.max)?;
            Ok(limit)
        })
        .collect::<PyResult<Vec<_>>>()?;
    d.set_item("limits", PyList::new(py, limits)?)?;
    Ok(d)
}

fn joints<'py>(py: Python<'py>, joints: &[JointInfo]) -> PyResult<Bound<'py, PyList>> {
    let joints = joints
        .iter()
        .map(|j| joint(py, j))
        .collect::<PyResult<Vec<_>>>()?;
    PyList::new(py, joints)
}

fn actuators<'py>(py: Python<'py>, list: &[ActuatorInfo]) -> PyResult<Bound<'py, PyList>> {
    let list = list
        .iter()
        .map(|a| {
            let d = PyDict::new(py);
            d.set_item("name", &a.name)?;
            d.set_item("type", &a.actuator_type)?;
            d.set_item("target", &a.target)?;
            d.set_item("ctrl_range", a.ctrl_range.map(|r| (r[0], r[1])))?;
            Ok(d)
        })
        .collect::<PyResult<Vec<_>>>()?;
    PyList::new(py, list)
}

/// What every env of a batch and a single env share: an [`EnvInfo`]'s fields, but its id.
fn write_env(py: Python<'_>, i: &EnvInfo, d: &Bound<'_, PyDict>) -> PyResult<()> {
    d.set_item("num_joints", i.num_joints)?;
    d.set_item("action_dim", i.action_dim)?;
    d.set_item("observation_dim", i.observation_dim)?;
    d.set_item("end_effector_ids", &i.end_effector_ids)?;
    d.set_item("dt", i.dt)?;
    d.set_item("substeps", i.substeps)?;
    d.set_item("max_steps", i.max_steps)?;
    d.set_item("joints", joints(py, &i.joints)?)?;
    d.set_item("observation_layout", i.observation_layout.clone())?;
    d.set_item(
        "units",
        match i.units {
            gymfleet_client::Units::Document => "document",
            gymfleet_client::Units::Si => "si",
        },
    )?;
    d.set_item("term_names", &i.term_names)?;
    d.set_item("free_bodies", &i.free_bodies)?;
    d.set_item("mocap_bodies", &i.mocap_bodies)?;
    d.set_item("moving_mass", i.moving_mass)?;
    d.set_item("actuators", actuators(py, &i.actuators)?)?;
    d.set_item("keyframes", &i.keyframes)?;
    d.set_item("heightfields", i.heightfields.clone())
}

/// A single env's description.
pub(crate) fn env_info<'py>(
    py: Python<'py>,
    i: &EnvInfo,
    server: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("env_id", &i.env_id)?;
    d.set_item("server", server)?;
    write_env(py, i, &d)?;
    Ok(d)
}

/// A batch's description; `shards` lists `(server, batch_id, start, stop)` per shard.
pub(crate) fn batch_info<'py>(
    py: Python<'py>,
    i: &BatchInfo,
    shards: Vec<(String, String, usize, usize)>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("batch_id", &i.batch_id)?;
    d.set_item("n_envs", i.n_envs)?;
    write_env(py, &i.env, &d)?;
    d.set_item("shards", PyList::new(py, shards)?)?;
    Ok(d)
}

/// An env's randomisation factors: `{"instances": [(name, mass, friction)], "joints":
/// [(name, damping, gain)]}`.
pub(crate) fn draws<'py>(
    py: Python<'py>,
    d: gymfleet_client::RandomizationDraws,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("instances", d.instances)?;
    out.set_item("joints", d.joints)?;
    Ok(out)
}

/// [`gymfleet_client::Bodies`] as a dict: `instances` and `sites` (lists of names), the
/// other fields float64 arrays, flat as the client has them.
pub(crate) fn bodies(py: Python<'_>, b: gymfleet_client::Bodies) -> PyResult<Bound<'_, PyDict>> {
    use numpy::PyArray1;
    let d = PyDict::new(py);
    d.set_item("instances", b.instances)?;
    d.set_item("sites", b.sites)?;
    d.set_item("sensors", b.sensors)?;
    d.set_item("sensor_types", b.sensor_types)?;
    d.set_item("sensor_dims", b.sensor_dims)?;
    for (key, values) in [
        ("masses", b.masses),
        ("centers_of_mass", b.centers_of_mass),
        ("inertias", b.inertias),
        ("velocities", b.velocities),
        ("contact_wrenches", b.contact_wrenches),
        ("about", b.about.to_vec()),
        ("site_poses", b.site_poses),
        ("actuator_forces", b.actuator_forces),
        ("sensordata", b.sensor_data),
    ] {
        d.set_item(key, PyArray1::from_vec(py, values))?;
    }
    Ok(d)
}
