//! Documents: conversion of MJCF, URDF and assembly JSON (with an assets archive) to
//! assembly JSON, building one env from a request, and the `--models` library.

use gymfleet_env::{EnvError, RobotEnv};

use crate::config::ServerConfig;
use crate::domain::{EnvRequest, JointLinks};
use crate::error::{Result, ServerError};
use crate::pool::{self, Lane};

use super::limits::{check_contact_work, check_step_work, check_structure};
use super::Simulation;

/// Parses, checks against the structural limits (for `n_envs` copies), and builds one
/// env; names the bodies of its non-fixed joints.
pub(super) fn build_env(
    request: EnvRequest,
    config: &ServerConfig,
    n_envs: usize,
) -> Result<(RobotEnv, JointLinks)> {
    let converted = convert_document(
        &request.document,
        request.format,
        &request.assets,
        &request.document_path,
    )?;
    let assembly = gymfleet_assembly::parse(&converted.json).map_err(EnvError::Document)?;
    check_structure(config, &assembly, request.config.end_effector_ids.len())?;
    let substeps = request.config.substeps;
    // Options are checked first (a substep count out of range is a bad argument, not a
    // large request); building one env is cheap, its copies are not made yet.
    let mut env = RobotEnv::new(&assembly, request.config)?;
    check_step_work(config, n_envs, substeps, assembly.total_dof())?;
    check_contact_work(config, &mut env, substeps)?;
    let name = |i: usize| {
        assembly
            .instances
            .get(i)
            .map(|inst| inst.name.clone())
            .unwrap_or_default()
    };
    // One entry per joint with an observed DOF, as `convert::replies::joints` lists them (an
    // unobserved loop-closing joint has none).
    let links = assembly
        .joints
        .iter()
        .filter(|j| j.observed_dof() > 0)
        .map(|j| (name(j.parent), name(j.child)))
        .collect();
    Ok((env, JointLinks(links)))
}

/// A document of `format` (`None`: detect) converted to assembly JSON, its mesh files read
/// from `assets` (an archive; empty: none), its relative references from the folder of
/// `document_path` in it (empty: the root).
pub(crate) fn convert_document(
    document: &str,
    format: Option<gymfleet_import::Format>,
    assets: &[u8],
    document_path: &str,
) -> Result<gymfleet_import::Conversion> {
    let folder = match document_path.rsplit_once('/') {
        Some((folder, _)) => gymfleet_import::asset_path("", folder).map_err(|reason| {
            ServerError::InvalidArgument {
                field: "document_path",
                reason,
            }
        })?,
        None => String::new(),
    };
    let assets = if assets.is_empty() {
        None
    } else {
        Some(gymfleet_import::Assets::from_archive(assets)?)
    };
    Ok(gymfleet_import::convert_in(
        document,
        format,
        assets.as_ref(),
        &folder,
    )?)
}

impl Simulation {
    /// A request naming a library model, with that model's document in its place.
    pub(super) fn resolve_model(&self, mut request: EnvRequest) -> Result<EnvRequest> {
        let Some(name) = request.model.take() else {
            return Ok(request);
        };
        let library = self.config.models.as_deref();
        match library.and_then(|l| l.get(&name)) {
            Some(model) => {
                request.document = model.document.clone();
                request.format = Some(gymfleet_import::Format::Json);
                Ok(request)
            }
            None => {
                let known = match library {
                    Some(l) if !l.is_empty() => {
                        let names: Vec<String> =
                            l.iter().take(16).map(|(n, _)| format!("{n:?}")).collect();
                        let more = l.len().saturating_sub(16);
                        if more > 0 {
                            format!("{} and {more} more", names.join(", "))
                        } else {
                            names.join(", ")
                        }
                    }
                    _ => "none: start the server with --models DIR".to_string(),
                };
                Err(ServerError::UnknownModel { name, known })
            }
        }
    }

    /// The library's models: name, format, DOFs, action length.
    pub(crate) fn models(&self) -> Vec<(String, gymfleet_import::Format, usize, usize)> {
        self.config.models.as_deref().map_or_else(Vec::new, |l| {
            l.iter()
                .map(|(n, m)| (n.to_string(), m.format, m.dofs, m.action_dim))
                .collect()
        })
    }

    /// A description as assembly JSON (checked by parsing it), its warnings and format.
    pub(crate) async fn convert(
        &self,
        document: String,
        format: Option<gymfleet_import::Format>,
        assets: Vec<u8>,
        document_path: String,
    ) -> Result<(String, Vec<String>, gymfleet_import::Format)> {
        self.check_document(&document)?;
        pool::run(&self.pool, Lane::Env, "ConvertDocument", move || {
            let converted = convert_document(&document, format, &assets, &document_path)?;
            gymfleet_assembly::parse(&converted.json).map_err(EnvError::Document)?;
            Ok((converted.json, converted.warnings, converted.format))
        })
        .await
    }
}
