//! [`Fleet`]: one connection per server of a fleet, and the placement of new envs and
//! batches on them. A fleet batch's shards live in [`crate::FleetBatch`].

use crate::client::{Client, ClientBuilder, DEFAULT_MAX_MESSAGE_BYTES};
use crate::endpoints::FleetEndpoints;
use crate::env::Env;
use crate::error::{ClientError, Result};
use crate::fanout::{join_all, on_server};
use crate::fleet_batch::{FleetBatch, Shard};
use crate::options::{BatchOptions, EnvOptions};
use crate::placement::{split_by_capacity, ServerCapacity};
use crate::types::ServerInfo;

/// Several gymfleet servers used as one: batches are sharded across them in proportion
/// to their simulation threads, single envs go to the least-loaded server.
///
/// It holds one connection ([`Client`]) per server and never balances requests: an
/// env's state lives on the one server that created it, and every call for it goes
/// there. Cloning is cheap and shares the connections.
///
/// ```no_run
/// use gymfleet_client::{ActionType, BatchOptions, Fleet, FleetEndpoints};
///
/// # async fn demo() -> gymfleet_client::Result<()> {
/// // Three pods of the StatefulSet "gymfleet" behind the headless Service "gymfleet".
/// let endpoints = FleetEndpoints::stateful_set("gymfleet", "gymfleet", "default", 3, 50051)?;
/// let fleet = Fleet::connect(endpoints).await?;
/// let document = std::fs::read_to_string("models/arm2.json").expect("model");
/// let mut batch = fleet
///     .create_batch(BatchOptions::new(document, 96).end_effectors(["forearm"]).seed(7))
///     .await?;
/// for shard in batch.placement() {
///     println!("{}: envs {:?}", shard.server, shard.envs);
/// }
/// let actions = vec![0.1_f32; batch.info().n_envs * batch.info().action_dim];
/// let step = batch.step(ActionType::Torque, &actions).await?;
/// assert_eq!(step.n_envs(), 96);
/// batch.close().await?;
/// # Ok(())
/// # }
/// ```
///
/// A fleet made by [`Fleet::connect`] needs every server at the start; one made by
/// [`Fleet::connect_available`] starts with the servers that answer and brings the others
/// in when they do.
#[derive(Debug, Clone)]
pub struct Fleet {
    servers: Vec<Client>,
    /// Whether placement leaves out the servers that do not answer
    /// ([`Fleet::connect_available`]) instead of failing on them.
    partial: bool,
}

impl Fleet {
    /// Connects to every server of `endpoints`, concurrently. Fails with the first
    /// server (in fleet order) that cannot be reached, naming it.
    ///
    /// This is the default because it is the safer one: a mistyped or stale address
    /// fails at once, and every fleet batch is spread over every server as configured,
    /// rather than the reachable ones quietly taking the whole load. Where servers come up
    /// in their own time (a StatefulSet's pods), use [`Fleet::connect_available`].
    pub async fn connect(endpoints: FleetEndpoints) -> Result<Self> {
        Self::connect_with_limit(endpoints, DEFAULT_MAX_MESSAGE_BYTES).await
    }

    /// Connects to the servers of `endpoints` that answer now, concurrently, and keeps a
    /// connection to each of the others that is tried again at every call: envs and
    /// batches are placed on the servers that answer when they are created, so a server
    /// that comes up later takes part from the next creation on. Fails only when no
    /// server answers ([`ClientError::Fleet`], with each one's reason), or on a setting
    /// that cannot work anywhere (a malformed address, a bad token).
    ///
    /// Envs step bitwise alike however a batch is placed, so the servers that answer
    /// change where envs live, never what they compute.
    pub async fn connect_available(endpoints: FleetEndpoints) -> Result<Self> {
        let settings = Client::builder("").max_message_bytes(DEFAULT_MAX_MESSAGE_BYTES);
        Self::connect_available_with(endpoints, &settings).await
    }

    /// [`Fleet::connect_available`], connecting every server with `settings`.
    pub async fn connect_available_with(
        endpoints: FleetEndpoints,
        settings: &ClientBuilder,
    ) -> Result<Self> {
        let addrs = endpoints.addrs();
        let connecting = addrs
            .iter()
            .map(|addr| settings.for_addr(addr.clone()).connect());
        let mut servers = Vec::with_capacity(addrs.len());
        let mut failures = Vec::new();
        for (addr, connected) in addrs.iter().zip(join_all(connecting).await) {
            match connected {
                Ok(client) => servers.push(client),
                Err(err @ ClientError::Connect { .. }) => {
                    failures.push(err.to_string());
                    // Connects at its first call, and again at each later one until then.
                    servers.push(settings.for_addr(addr.clone()).lazy(true).connect().await?);
                }
                Err(other) => return Err(other),
            }
        }
        if failures.len() == addrs.len() {
            return Err(ClientError::Fleet {
                message: format!("no server of the fleet answered: {}", failures.join(" | ")),
            });
        }
        Ok(Fleet {
            servers,
            partial: true,
        })
    }

    /// [`Fleet::connect`], with [`Client::connect_with_limit`]'s message limit.
    pub async fn connect_with_limit(
        endpoints: FleetEndpoints,
        max_message_bytes: usize,
    ) -> Result<Self> {
        let settings = Client::builder("").max_message_bytes(max_message_bytes);
        Self::connect_with(endpoints, &settings).await
    }

    /// [`Fleet::connect`], connecting every server with `settings` (its token, TLS,
    /// timeouts and keepalive; its address is replaced by each server's).
    pub async fn connect_with(endpoints: FleetEndpoints, settings: &ClientBuilder) -> Result<Self> {
        let connecting = endpoints
            .addrs()
            .iter()
            .map(|addr| settings.for_addr(addr.clone()).connect());
        let servers = join_all(connecting)
            .await
            .into_iter()
            .collect::<Result<Vec<_>>>()?;
        Ok(Fleet {
            servers,
            partial: false,
        })
    }

    /// A fleet of already connected clients, one per server.
    pub fn from_clients(servers: Vec<Client>) -> Result<Self> {
        FleetEndpoints::new(servers.iter().map(|c| c.addr().to_string()))?;
        Ok(Fleet {
            servers,
            partial: false,
        })
    }

    /// Whether placement leaves out servers that do not answer (a fleet made by
    /// [`Fleet::connect_available`]).
    pub fn places_on_answering_servers(&self) -> bool {
        self.partial
    }

    /// The servers' addresses, in fleet order.
    pub fn servers(&self) -> Vec<&str> {
        self.servers.iter().map(Client::addr).collect()
    }

    /// The connection to each server, in fleet order.
    pub fn clients(&self) -> &[Client] {
        &self.servers
    }

    /// Every server's [`ServerInfo`], asked concurrently, in fleet order. Fails with
    /// [`ClientError::OnServer`] naming the first server that did not answer.
    pub async fn server_infos(&self) -> Result<Vec<ServerInfo>> {
        self.ask_infos().await.into_iter().collect()
    }

    async fn ask_infos(&self) -> Vec<Result<ServerInfo>> {
        join_all(self.servers.iter().map(|client| {
            let client = client.clone();
            async move {
                client
                    .server_info()
                    .await
                    .map_err(|e| on_server(&client, e))
            }
        }))
        .await
    }

    /// Creates one env on the least-loaded server: the one with the fewest envs (single
    /// and batched) per simulation thread, the earlier one on a tie. Servers that do not
    /// answer or are full are skipped; [`Env::server`] says where it went.
    pub async fn create_env(&self, options: EnvOptions) -> Result<Env> {
        let infos = self.ask_infos().await;
        let mut best: Option<(usize, u128, u128)> = None;
        let mut first_error = None;
        for (i, info) in infos.into_iter().enumerate() {
            let info = match info {
                Ok(info) => info,
                Err(err) => {
                    first_error.get_or_insert(err);
                    continue;
                }
            };
            let held = u128::from(info.envs) + u128::from(info.batch_envs);
            let full = info.limits.max_envs != 0 && held >= u128::from(info.limits.max_envs);
            if info.threads == 0 || full {
                continue;
            }
            let threads = u128::from(info.threads);
            // held / threads < best_held / best_threads, without division.
            if best.is_none_or(|(_, h, t)| held * t < h * threads) {
                best = Some((i, held, threads));
            }
        }
        let Some((i, _, _)) = best else {
            return Err(first_error.unwrap_or_else(|| ClientError::Fleet {
                message: "no server has room for another env".to_string(),
            }));
        };
        let client = &self.servers[i];
        client
            .create_env(options)
            .await
            .map_err(|e| on_server(client, e))
    }

    /// Creates a batch of `options.n_envs()` envs sharded across the servers in
    /// proportion to their simulation threads (see [`FleetBatch`]).
    ///
    /// Env `i` of the fleet batch is seeded exactly as env `i` of a single-server batch
    /// with the same options: each shard gets the seed offset of its first env. Fails
    /// with [`ClientError::OnServer`] naming the first server that cannot take part;
    /// shards already created are closed first, so nothing is left behind.
    pub async fn create_batch(&self, options: BatchOptions) -> Result<FleetBatch> {
        let n_envs = options.n_envs();
        if n_envs == 0 {
            return Err(ClientError::InvalidArgument {
                reason: crate::ErrorReason::InvalidField,
                message: "n_envs: expected at least 1, got 0".to_string(),
            });
        }
        let capacities = self.capacities().await?;
        let shares = split_by_capacity(n_envs, &capacities).map_err(|reason| {
            ClientError::ResourceExhausted {
                reason: crate::ErrorReason::LimitExceeded,
                limit: None,
                message: format!("fleet batch of {n_envs} envs: {reason}"),
                code: tonic::Code::ResourceExhausted,
            }
        })?;

        let base_offset = options.seed_offset_base();
        let mut start = 0;
        let mut ranges = Vec::new();
        let mut creating = Vec::new();
        for (client, share) in self.servers.iter().zip(shares) {
            if share == 0 {
                continue;
            }
            let envs = start..start + share;
            start += share;
            let shard_options = options
                .clone()
                .with_n_envs(share)
                .seed_offset(base_offset.wrapping_add(envs.start as u64));
            let client = client.clone();
            ranges.push(envs);
            creating.push(async move {
                client
                    .create_batch(shard_options)
                    .await
                    .map_err(|e| on_server(&client, e))
            });
        }
        let created = join_all(creating).await;
        let mut batches = Vec::with_capacity(created.len());
        let mut first_error = None;
        for result in created {
            match result {
                Ok(batch) => batches.push(batch),
                Err(err) => {
                    first_error.get_or_insert(err);
                }
            }
        }
        if let Some(err) = first_error {
            close_quietly(batches).await;
            return Err(err);
        }
        let shards = batches
            .into_iter()
            .zip(ranges)
            .map(|(batch, envs)| Shard::new(batch, envs))
            .collect();
        match FleetBatch::new(shards) {
            Ok(batch) => Ok(batch),
            Err((err, batches)) => {
                close_quietly(batches).await;
                Err(err)
            }
        }
    }
}

impl Fleet {
    /// What each server may take for a new batch. A fleet of [`Fleet::connect`] needs
    /// every server's answer; one of [`Fleet::connect_available`] gives a server that
    /// does not answer no share, and fails only when none answers.
    async fn capacities(&self) -> Result<Vec<ServerCapacity>> {
        if !self.partial {
            let infos = self.server_infos().await?;
            return Ok(infos.iter().map(ServerCapacity::from_info).collect());
        }
        let answers = self.ask_infos().await;
        if answers.iter().all(Result::is_err) {
            if let Some(Err(first)) = answers.into_iter().next() {
                return Err(first);
            }
            unreachable!("a fleet has at least one server");
        }
        Ok(answers
            .iter()
            .map(|answer| match answer {
                Ok(info) => ServerCapacity::from_info(info),
                Err(_) => ServerCapacity::NONE,
            })
            .collect())
    }
}

/// Closes batches, ignoring errors: a cleanup after a failed creation.
async fn close_quietly(batches: Vec<crate::Batch>) {
    join_all(
        batches
            .into_iter()
            .map(|batch| async move { batch.close().await }),
    )
    .await;
}
