//! The create requests (`CreateEnvRequest`, `CreateBatchRequest`, `ForkRequest`) as
//! domain requests: the env's options (`EnvOptions`, or the deprecated flat fields that
//! older clients send), its task and randomisation, and a batch's autoreset.

use gymfleet_batch::Autoreset;
use gymfleet_env::{
    EnvConfig, PdGains, Randomization, ReachTarget, TaskKind, TaskSpec, TermsTask, Units,
};
use gymfleet_proto::v1 as pb;

use crate::domain::{BatchRequest, EnvRequest, ForkRequest};
use crate::error::{Result, ServerError};

fn autoreset(raw: i32) -> Result<Autoreset> {
    match pb::Autoreset::try_from(raw) {
        Ok(pb::Autoreset::Disabled) => Ok(Autoreset::Disabled),
        Ok(pb::Autoreset::SameStep) => Ok(Autoreset::SameStep),
        Ok(pb::Autoreset::NextStep) => Ok(Autoreset::NextStep),
        Err(_) => Err(ServerError::InvalidArgument {
            field: "autoreset",
            reason: format!(
                "expected AUTORESET_DISABLED, AUTORESET_SAME_STEP or AUTORESET_NEXT_STEP, got \
                 unknown value {raw}"
            ),
        }),
    }
}

/// A request's `DocumentFormat`: `None` to detect.
pub(crate) fn document_format(raw: i32) -> Result<Option<gymfleet_import::Format>> {
    use gymfleet_import::Format;
    match pb::DocumentFormat::try_from(raw) {
        Ok(pb::DocumentFormat::Unspecified) => Ok(None),
        Ok(pb::DocumentFormat::Json) => Ok(Some(Format::Json)),
        Ok(pb::DocumentFormat::Urdf) => Ok(Some(Format::Urdf)),
        Ok(pb::DocumentFormat::Mjcf) => Ok(Some(Format::Mjcf)),
        Err(_) => Err(ServerError::InvalidArgument {
            field: "format",
            reason: format!(
                "expected DOCUMENT_FORMAT_UNSPECIFIED, _JSON, _URDF or _MJCF, got unknown value {raw}"
            ),
        }),
    }
}

/// The deprecated flat option fields of a `CreateEnvRequest` or `CreateBatchRequest` (the
/// two name them alike) as the [`pb::EnvOptions`] they stand for. Read once per request,
/// only to accept what older clients send.
macro_rules! flat_options {
    ($r:ident) => {{
        #[allow(deprecated)]
        let flat = pb::EnvOptions {
            document_json: std::mem::take(&mut $r.document_json),
            end_effector_ids: std::mem::take(&mut $r.end_effector_ids),
            dt: $r.dt,
            substeps: $r.substeps,
            max_steps: $r.max_steps,
            seed: $r.seed,
            pd_gains: $r.pd_gains.take(),
            reset_noise: $r.reset_noise,
            task: $r.task.take(),
            randomize: $r.randomize.take(),
            format: $r.format,
            model: std::mem::take(&mut $r.model),
            assets: std::mem::take(&mut $r.assets),
            units: $r.units,
            document_path: std::mem::take(&mut $r.document_path),
        };
        flat
    }};
}

/// A create request's options: its `options`, or its deprecated flat fields (`flat`),
/// refusing a request that gives both.
fn options_of(options: Option<pb::EnvOptions>, flat: pb::EnvOptions) -> Result<pb::EnvOptions> {
    match options {
        None => Ok(flat),
        Some(options) if flat == pb::EnvOptions::default() => Ok(options),
        Some(_) => Err(ServerError::InvalidArgument {
            field: "options",
            reason: "give the env's options in `options` or in the deprecated flat fields \
                     (document_json, dt, ...), not both"
                .to_string(),
        }),
    }
}

fn env_request(options: pb::EnvOptions) -> Result<EnvRequest> {
    let pb::EnvOptions {
        document_json: document,
        format,
        model,
        assets,
        document_path,
        end_effector_ids,
        dt,
        substeps,
        max_steps,
        seed,
        pd_gains,
        reset_noise,
        task,
        randomize,
        units,
    } = options;
    let defaults = EnvConfig::default();
    let pd_gains = pd_gains
        .filter(|g| !(g.kp.is_empty() && g.kd.is_empty()))
        .map(|g| PdGains { kp: g.kp, kd: g.kd });
    if !model.is_empty() && !document.is_empty() {
        return Err(ServerError::InvalidArgument {
            field: "model",
            reason: "give document_json or model, not both".to_string(),
        });
    }
    if !model.is_empty() && !assets.is_empty() {
        return Err(ServerError::InvalidArgument {
            field: "assets",
            reason:
                "a library model brings its own mesh files: give assets with document_json only"
                    .to_string(),
        });
    }
    Ok(EnvRequest {
        document,
        format: document_format(format)?,
        model: (!model.is_empty()).then_some(model),
        assets,
        document_path,
        config: EnvConfig {
            end_effector_ids,
            // 0 means "the document's, else the default" (resolved by the env); anything
            // else (negative, NaN) is the env's to reject.
            dt,
            substeps: if substeps == 0 {
                defaults.substeps
            } else {
                substeps
            },
            max_steps: if max_steps == 0 {
                defaults.max_steps
            } else {
                max_steps
            },
            seed: seed.unwrap_or(0),
            pd_gains,
            reset_noise: reset_noise.unwrap_or(0.0),
            task: task.map(task_spec).transpose()?,
            randomize: randomize.map(|r| {
                let range = |r: Option<pb::Range>| r.map(|r| [r.min, r.max]);
                Randomization {
                    mass_scale: range(r.mass_scale),
                    friction_scale: range(r.friction_scale),
                    damping_scale: range(r.damping_scale),
                    gain_scale: range(r.gain_scale),
                }
            }),
            units: units_of(units)?,
        },
    })
}

/// A request's `units`.
fn units_of(raw: i32) -> Result<Units> {
    match pb::Units::try_from(raw) {
        Ok(pb::Units::Document) => Ok(Units::Document),
        Ok(pb::Units::Si) => Ok(Units::Si),
        Err(_) => Err(ServerError::InvalidArgument {
            field: "units",
            reason: format!("expected UNITS_DOCUMENT or UNITS_SI, got unknown value {raw}"),
        }),
    }
}

/// Longest terms task JSON accepted, bytes.
const MAX_TERMS_JSON: usize = 64 * 1024;

fn vec3(v: pb::Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// A proto `Task` as the env's `TaskSpec`; the env checks the values against the robot.
fn task_spec(t: pb::Task) -> Result<TaskSpec> {
    use pb::task::Kind;
    let kind = match t.kind {
        None => {
            return Err(ServerError::InvalidArgument {
                field: "task.kind",
                reason: "expected one of reach, track, upright, terms".to_string(),
            })
        }
        Some(Kind::Reach(r)) => TaskKind::Reach {
            end_effector: r.end_effector,
            point: r.point.map(vec3),
            target: match (r.target, r.target_box) {
                (Some(t), None) => ReachTarget::Fixed(vec3(t)),
                (None, Some(b)) => ReachTarget::Box {
                    min: vec3(b.min.unwrap_or_default()),
                    max: vec3(b.max.unwrap_or_default()),
                },
                (Some(_), Some(_)) | (None, None) => {
                    return Err(ServerError::InvalidArgument {
                        field: "task.reach.target",
                        reason: "expected exactly one of target and target_box".to_string(),
                    })
                }
            },
            success_radius: r.success_radius,
            terminate_on_success: r.terminate_on_success,
        },
        Some(Kind::Track(r)) => TaskKind::Track {
            targets: r.targets,
            tolerance: r.tolerance,
            terminate_on_success: r.terminate_on_success,
        },
        Some(Kind::Upright(r)) => TaskKind::Upright {
            instance: r.instance,
            axis: r.axis.map_or([0.0, 0.0, 1.0], vec3),
            max_tilt_deg: r.max_tilt_deg,
        },
        Some(Kind::Terms(r)) => {
            if r.json.len() > MAX_TERMS_JSON {
                return Err(ServerError::InvalidArgument {
                    field: "task.terms.json",
                    reason: format!(
                        "expected at most {MAX_TERMS_JSON} bytes of JSON, got {}",
                        r.json.len()
                    ),
                });
            }
            TaskKind::Terms(TermsTask::from_json(&r.json)?)
        }
    };
    Ok(TaskSpec {
        kind,
        action_cost: f64::from(t.action_cost),
    })
}

impl TryFrom<pb::CreateEnvRequest> for EnvRequest {
    type Error = ServerError;

    fn try_from(mut r: pb::CreateEnvRequest) -> Result<Self> {
        let flat = flat_options!(r);
        env_request(options_of(r.options, flat)?)
    }
}

impl TryFrom<pb::CreateBatchRequest> for BatchRequest {
    type Error = ServerError;

    fn try_from(r: pb::CreateBatchRequest) -> Result<Self> {
        if r.n_envs == 0 {
            return Err(ServerError::InvalidArgument {
                field: "n_envs",
                reason: "expected at least 1 environment, got 0".to_string(),
            });
        }
        let autoreset = autoreset(r.autoreset)?;
        let mut r = r;
        let flat = flat_options!(r);
        let options = options_of(r.options.take(), flat)?;
        let (seed, n_envs, seed_offset) = (options.seed, r.n_envs, r.seed_offset);
        Ok(BatchRequest {
            seed,
            env: env_request(options)?,
            n_envs: usize::try_from(n_envs).unwrap_or(usize::MAX),
            autoreset,
            seed_offset,
        })
    }
}

impl TryFrom<pb::ForkRequest> for ForkRequest {
    type Error = ServerError;

    fn try_from(r: pb::ForkRequest) -> Result<Self> {
        if r.n_envs == 0 {
            return Err(ServerError::InvalidArgument {
                field: "n_envs",
                reason: "expected at least 1 environment, got 0".to_string(),
            });
        }
        Ok(ForkRequest {
            state: r.state,
            n_envs: usize::try_from(r.n_envs).unwrap_or(usize::MAX),
            autoreset: autoreset(r.autoreset)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use gymfleet_env::{DEFAULT_MAX_STEPS, DEFAULT_SUBSTEPS};

    use super::*;

    /// A `CreateEnvRequest` with `options`.
    fn with(options: pb::EnvOptions) -> pb::CreateEnvRequest {
        pb::CreateEnvRequest {
            options: Some(options),
            ..Default::default()
        }
    }

    #[test]
    #[allow(deprecated)]
    fn the_deprecated_flat_fields_are_read_and_not_mixed_with_options() {
        let flat = EnvRequest::try_from(pb::CreateEnvRequest {
            document_json: "{}".into(),
            substeps: 3,
            seed: Some(4),
            ..Default::default()
        })
        .unwrap();
        let nested = EnvRequest::try_from(with(pb::EnvOptions {
            document_json: "{}".into(),
            substeps: 3,
            seed: Some(4),
            ..Default::default()
        }))
        .unwrap();
        assert_eq!(format!("{flat:?}"), format!("{nested:?}"));
        let batch = BatchRequest::try_from(pb::CreateBatchRequest {
            dt: 0.01,
            seed: Some(5),
            n_envs: 2,
            ..Default::default()
        })
        .unwrap();
        assert_eq!((batch.env.config.dt, batch.seed), (0.01, Some(5)));
        let Err(both) = EnvRequest::try_from(pb::CreateEnvRequest {
            dt: 0.01,
            ..with(pb::EnvOptions::default())
        }) else {
            panic!("options and flat fields together are refused")
        };
        assert_eq!(
            both.to_string(),
            "options: give the env's options in `options` or in the deprecated flat fields \
             (document_json, dt, ...), not both"
        );
    }

    #[test]
    fn zero_means_the_default() {
        let r = EnvRequest::try_from(with(pb::EnvOptions {
            document_json: "{}".into(),
            pd_gains: Some(pb::PdGains::default()),
            reset_noise: Some(0.0),
            ..Default::default()
        }))
        .unwrap();
        assert_eq!(
            r.config.dt, 0.0,
            "the document's, else DEFAULT_DT: the env resolves it"
        );
        assert_eq!(r.config.substeps, DEFAULT_SUBSTEPS);
        assert_eq!(r.config.max_steps, DEFAULT_MAX_STEPS);
        assert_eq!(r.config.seed, 0);
        assert_eq!(r.config.pd_gains, None, "empty gains are the defaults");
    }

    #[test]
    fn units_and_terms_tasks_are_read_and_checked() {
        let r = EnvRequest::try_from(with(pb::EnvOptions {
            units: pb::Units::Si as i32,
            task: Some(pb::Task {
                kind: Some(pb::task::Kind::Terms(pb::TermsTask {
                    json: r#"{"terms": [{"name": "c", "ctrl_cost": {}}]}"#.into(),
                })),
                action_cost: 0.0,
            }),
            ..Default::default()
        }))
        .unwrap();
        assert_eq!(r.config.units, Units::Si);
        assert!(matches!(
            r.config.task.map(|t| t.kind),
            Some(TaskKind::Terms(t)) if t.terms.len() == 1
        ));
        let Err(err) = EnvRequest::try_from(with(pb::EnvOptions {
            units: 7,
            ..Default::default()
        })) else {
            panic!("an unknown units value is refused")
        };
        assert_eq!(
            err.to_string(),
            "units: expected UNITS_DOCUMENT or UNITS_SI, got unknown value 7"
        );
    }

    #[test]
    fn given_values_pass_through() {
        let r = EnvRequest::try_from(with(pb::EnvOptions {
            end_effector_ids: vec!["arm".into()],
            dt: -1.0,
            substeps: 2,
            max_steps: 7,
            seed: Some(9),
            pd_gains: Some(pb::PdGains {
                kp: vec![1.0],
                kd: vec![],
            }),
            ..Default::default()
        }))
        .unwrap();
        // Range checks are the env's: a negative dt reaches it unchanged.
        assert_eq!(r.config.dt, -1.0);
        assert_eq!(
            (r.config.substeps, r.config.max_steps, r.config.seed),
            (2, 7, 9)
        );
        assert_eq!(r.config.end_effector_ids, ["arm"]);
        assert_eq!(r.config.pd_gains.unwrap().kp, [1.0]);
    }

    #[test]
    fn reset_noise_reaches_the_env_config() {
        let r = EnvRequest::try_from(with(pb::EnvOptions {
            reset_noise: Some(0.5),
            ..Default::default()
        }))
        .unwrap();
        assert_eq!(r.config.reset_noise, 0.5);
    }

    #[test]
    fn batch_requests_check_size_and_autoreset() {
        let request = |n_envs, autoreset| pb::CreateBatchRequest {
            n_envs,
            autoreset,
            seed_offset: 4,
            ..Default::default()
        };
        let r = BatchRequest::try_from(request(3, pb::Autoreset::NextStep as i32)).unwrap();
        assert_eq!(
            (r.n_envs, r.autoreset, r.seed_offset),
            (3, Autoreset::NextStep, 4)
        );
        assert!(BatchRequest::try_from(request(0, 0)).is_err());
        assert!(BatchRequest::try_from(request(1, 7)).is_err());
    }
}
