//! What an env looks like and what it drew: randomization draws, scenes and rendered frames.

use gymfleet_env::DrawReport;

use crate::domain::{DrawsOf, RenderOf, Rendered};
use crate::error::{Result, ServerError};
use crate::pool::Lane;
use crate::tenant::Tenant;

use super::Simulation;

impl Simulation {
    /// The randomisation factors of an env, or of env `index` of a batch.
    pub(crate) async fn randomization(
        &self,
        tenant: &Tenant,
        target: DrawsOf,
    ) -> Result<DrawReport> {
        match target {
            DrawsOf::Env(id) => {
                let env_id = id.clone();
                self.on_env(tenant, &env_id, "GetRandomization", move |open| {
                    open.env.draws().ok_or(ServerError::NotRandomized { id })
                })
                .await
            }
            DrawsOf::BatchEnv(id, index) => {
                let batch_id = id.clone();
                self.on_batch(
                    tenant,
                    &batch_id,
                    Lane::Env,
                    "GetRandomization",
                    move |open| {
                        let n_envs = open.batch.n_envs();
                        if index >= n_envs {
                            return Err(ServerError::EnvIndex { index, n_envs });
                        }
                        open.batch.draws(index).ok_or(ServerError::NotRandomized {
                            id: format!("{id}[{index}]"),
                        })
                    },
                )
                .await
            }
        }
    }

    /// An env's scene (shapes and poses), read on the pool.
    pub(crate) async fn scene(&self, tenant: &Tenant, id: &str) -> Result<gymfleet_env::Scene> {
        self.on_env(tenant, id, "GetScene", |open| Ok(open.env.scene()))
            .await
    }

    /// A picture of an env, or of env `index` of a batch, taken on the pool.
    pub(crate) async fn render(&self, tenant: &Tenant, request: RenderOf) -> Result<Rendered> {
        let RenderOf {
            of,
            camera,
            width,
            height,
        } = request;
        let draw = move |scene: gymfleet_env::Scene| -> Result<Rendered> {
            let frame = gymfleet_render::render(&scene, &camera, width, height)?;
            Ok(Rendered {
                png: frame.to_png(),
                width: frame.width,
                height: frame.height,
                description: gymfleet_render::describe(&scene, &frame, &camera),
                grid_mm: frame.grid_mm,
            })
        };
        match of {
            DrawsOf::Env(id) => {
                self.on_env(tenant, &id, "Render", move |open| draw(open.env.scene()))
                    .await
            }
            DrawsOf::BatchEnv(id, index) => {
                let batch_id = id.clone();
                self.on_batch(tenant, &batch_id, Lane::Env, "Render", move |open| {
                    let n_envs = open.batch.n_envs();
                    let scene = open
                        .batch
                        .scene(index)
                        .ok_or(ServerError::EnvIndex { index, n_envs })?;
                    draw(scene)
                })
                .await
            }
        }
    }
}
