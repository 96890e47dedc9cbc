//! [`Fleet`]: the gymfleet servers this adapter talks to (connected lazily, so a server
//! that is down is a tool error, not a startup failure), where new envs and batches are
//! placed, and the adapter's own id table: `sim_<n>` and `batch_<n>` ids mapped to client
//! handles and the server that holds them, so ids from different servers never collide.

use std::collections::BTreeMap;
use std::future::Future;
use std::sync::{Mutex, MutexGuard};
use std::time::Duration;

use gymfleet_client::{
    Batch, BatchOptions, Client, ClientBuilder, ClientError, Env, EnvOptions, ErrorReason,
};
use tokio::sync::OnceCell;
use tokio::task::JoinSet;

use crate::errors::{self, IdKind, McpError, Result, Subject};

/// Prefix of the adapter's env ids.
pub(crate) const ENV_PREFIX: &str = "sim_";
/// Prefix of the adapter's batch ids.
pub(crate) const BATCH_PREFIX: &str = "batch_";
/// How long connecting to a server may take.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(5);
/// How long closing everything at shutdown may take.
const CLOSE_TIMEOUT: Duration = Duration::from_secs(5);
/// Open ids listed in an "unknown id" message.
const LISTED_IDS: usize = 10;

/// A handle the adapter handed out: its id, the client handle, and its server's index.
#[derive(Debug, Clone)]
pub(crate) struct Placed<T> {
    /// The adapter's id (`sim_<n>` or `batch_<n>`).
    pub(crate) id: String,
    /// The client handle.
    pub(crate) handle: T,
    /// Index of the server holding it.
    pub(crate) server: usize,
}

#[derive(Debug)]
struct Server {
    addr: String,
    /// How to connect to it (token, TLS, timeouts).
    settings: ClientBuilder,
    client: OnceCell<Client>,
}

#[derive(Debug, Default)]
struct Table {
    next_env: u64,
    next_batch: u64,
    envs: BTreeMap<u64, Placed<Env>>,
    batches: BTreeMap<u64, (Placed<Batch>, u64)>,
    /// Envs held per server (a batch counts its n_envs).
    load: Vec<u64>,
}

/// The servers and the id table. Shared by every MCP session of the process.
#[derive(Debug)]
pub(crate) struct Fleet {
    servers: Vec<Server>,
    table: Mutex<Table>,
}

/// The `n` of `id` if it is exactly `<prefix><n>`.
fn number(id: &str, prefix: &str) -> Option<u64> {
    let n = id.strip_prefix(prefix)?.parse::<u64>().ok()?;
    (format!("{prefix}{n}") == id).then_some(n)
}

fn listing<'a>(ids: impl ExactSizeIterator<Item = &'a String>) -> String {
    let total = ids.len();
    if total == 0 {
        return "none".to_string();
    }
    let mut text = ids
        .take(LISTED_IDS)
        .map(String::as_str)
        .collect::<Vec<_>>()
        .join(", ");
    if total > LISTED_IDS {
        text.push_str(&format!(", and {} more", total - LISTED_IDS));
    }
    text
}

impl Fleet {
    /// A fleet of the servers at `addrs` (at least one), none connected yet.
    /// `settings` carries the token and TLS settings every connection uses.
    pub(crate) fn new(addrs: Vec<String>, settings: ClientBuilder) -> Self {
        let servers: Vec<Server> = addrs
            .into_iter()
            .map(|addr| Server {
                settings: settings
                    .for_addr(addr.clone())
                    .connect_timeout(Some(CONNECT_TIMEOUT)),
                addr,
                client: OnceCell::new(),
            })
            .collect();
        let table = Table {
            load: vec![0; servers.len()],
            ..Table::default()
        };
        Fleet {
            servers,
            table: Mutex::new(table),
        }
    }

    /// The server addresses, in the order given.
    pub(crate) fn addrs(&self) -> Vec<&str> {
        self.servers.iter().map(|s| s.addr.as_str()).collect()
    }

    /// The address of server `server`.
    pub(crate) fn addr(&self, server: usize) -> &str {
        self.servers.get(server).map_or("?", |s| s.addr.as_str())
    }

    fn table(&self) -> MutexGuard<'_, Table> {
        // The table holds no invariant a panic could break halfway.
        self.table
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    async fn client(&self, server: usize) -> Result<Client, ClientError> {
        let server = &self.servers[server];
        let connect = || async {
            match tokio::time::timeout(CONNECT_TIMEOUT, server.settings.clone().connect()).await {
                Ok(result) => result,
                Err(_) => Err(ClientError::Connect {
                    addr: server.addr.clone(),
                    reason: format!("no answer within {} s", CONNECT_TIMEOUT.as_secs()),
                }),
            }
        };
        server.client.get_or_try_init(connect).await.cloned()
    }

    /// Creates something on the least-loaded reachable server; unreachable servers are
    /// skipped, any other refusal is final.
    async fn place<T, F, Fut>(&self, create: F) -> Result<(usize, T)>
    where
        F: Fn(Client) -> Fut,
        Fut: Future<Output = Result<T, ClientError>>,
    {
        let mut order: Vec<usize> = (0..self.servers.len()).collect();
        {
            let table = self.table();
            order.sort_by_key(|&i| table.load[i]);
        }
        let mut failures = Vec::new();
        for server in order {
            let created = match self.client(server).await {
                Ok(client) => create(client).await,
                Err(err) => Err(err),
            };
            match created {
                Ok(handle) => return Ok((server, handle)),
                Err(err) => match errors::unreachable(&err, self.addr(server)) {
                    Some(text) => {
                        tracing::warn!(server = self.addr(server), "{text}");
                        failures.push(text);
                    }
                    None => {
                        return Err(McpError::Server {
                            message: err.to_string(),
                        })
                    }
                },
            }
        }
        Err(McpError::NoServerReachable { failures })
    }

    /// The model library of the first reachable server (the least loaded first).
    pub(crate) async fn list_models(&self) -> Result<Vec<gymfleet_client::ModelInfo>> {
        let (_, models) = self
            .place(|client| async move { client.list_models().await })
            .await?;
        Ok(models)
    }

    /// Creates an env and gives it the next `sim_<n>` id.
    pub(crate) async fn create_env(&self, options: EnvOptions) -> Result<Placed<Env>> {
        let (server, env) = self
            .place(|client| {
                let options = options.clone();
                async move { client.create_env(options).await }
            })
            .await?;
        let mut table = self.table();
        table.next_env += 1;
        let n = table.next_env;
        table.load[server] += 1;
        let placed = Placed {
            id: format!("{ENV_PREFIX}{n}"),
            handle: env,
            server,
        };
        table.envs.insert(n, placed.clone());
        Ok(placed)
    }

    /// Creates a batch and gives it the next `batch_<n>` id.
    pub(crate) async fn create_batch(&self, options: BatchOptions) -> Result<Placed<Batch>> {
        let weight = options.n_envs() as u64;
        let (server, batch) = self
            .place(|client| {
                let options = options.clone();
                async move { client.create_batch(options).await }
            })
            .await?;
        let mut table = self.table();
        table.next_batch += 1;
        let n = table.next_batch;
        table.load[server] += weight;
        let placed = Placed {
            id: format!("{BATCH_PREFIX}{n}"),
            handle: batch,
            server,
        };
        table.batches.insert(n, (placed.clone(), weight));
        Ok(placed)
    }

    /// The env `id`, or a message naming it and the open envs.
    pub(crate) fn env(&self, id: &str) -> Result<Placed<Env>> {
        let table = self.table();
        if let Some(placed) = number(id, ENV_PREFIX).and_then(|n| table.envs.get(&n)) {
            return Ok(placed.clone());
        }
        if number(id, BATCH_PREFIX).is_some_and(|n| table.batches.contains_key(&n)) {
            return Err(McpError::WrongIdKind {
                id: id.to_string(),
                expected: IdKind::Env,
            });
        }
        Err(McpError::UnknownId {
            id: id.to_string(),
            kind: IdKind::Env,
            open: listing(table.envs.values().map(|p| &p.id)),
        })
    }

    /// The batch `id`, or a message naming it and the open batches.
    pub(crate) fn batch(&self, id: &str) -> Result<Placed<Batch>> {
        let table = self.table();
        if let Some((placed, _)) = number(id, BATCH_PREFIX).and_then(|n| table.batches.get(&n)) {
            return Ok(placed.clone());
        }
        if number(id, ENV_PREFIX).is_some_and(|n| table.envs.contains_key(&n)) {
            return Err(McpError::WrongIdKind {
                id: id.to_string(),
                expected: IdKind::Batch,
            });
        }
        Err(McpError::UnknownId {
            id: id.to_string(),
            kind: IdKind::Batch,
            open: listing(table.batches.values().map(|(p, _)| &p.id)),
        })
    }

    /// Drops env `id` from the table.
    pub(crate) fn forget_env(&self, id: &str) {
        let mut table = self.table();
        if let Some(placed) = number(id, ENV_PREFIX).and_then(|n| table.envs.remove(&n)) {
            table.load[placed.server] = table.load[placed.server].saturating_sub(1);
        }
    }

    /// Drops batch `id` from the table.
    pub(crate) fn forget_batch(&self, id: &str) {
        let mut table = self.table();
        if let Some((placed, weight)) =
            number(id, BATCH_PREFIX).and_then(|n| table.batches.remove(&n))
        {
            table.load[placed.server] = table.load[placed.server].saturating_sub(weight);
        }
    }

    /// The message for a failed call on env `placed`; forgets it if the server lost it.
    pub(crate) fn env_failed(&self, placed: &Placed<Env>, err: &ClientError) -> McpError {
        if err.reason() == Some(ErrorReason::EnvNotFound) {
            self.forget_env(&placed.id);
        }
        errors::on_subject(
            err,
            Subject {
                kind: IdKind::Env,
                id: &placed.id,
                server_id: placed.handle.id(),
                addr: self.addr(placed.server),
            },
        )
    }

    /// The message for a failed call on batch `placed`; forgets it if the server lost it.
    pub(crate) fn batch_failed(&self, placed: &Placed<Batch>, err: &ClientError) -> McpError {
        if err.reason() == Some(ErrorReason::BatchNotFound) {
            self.forget_batch(&placed.id);
        }
        errors::on_subject(
            err,
            Subject {
                kind: IdKind::Batch,
                id: &placed.id,
                server_id: placed.handle.id(),
                addr: self.addr(placed.server),
            },
        )
    }

    /// Closes every env and batch still open (at shutdown), waiting at most a few seconds
    /// for servers that do not answer.
    pub(crate) async fn close_all(&self) {
        let (envs, batches) = {
            let mut table = self.table();
            let envs = std::mem::take(&mut table.envs);
            let batches = std::mem::take(&mut table.batches);
            table.load.iter_mut().for_each(|l| *l = 0);
            (envs, batches)
        };
        if envs.is_empty() && batches.is_empty() {
            return;
        }
        let mut closing = JoinSet::new();
        for placed in envs.into_values() {
            closing.spawn(async move { (placed.id, placed.handle.close().await) });
        }
        for (placed, _) in batches.into_values() {
            closing.spawn(async move { (placed.id, placed.handle.close().await) });
        }
        let total = closing.len();
        let drain = async {
            while let Some(done) = closing.join_next().await {
                if let Ok((id, Err(err))) = done {
                    tracing::debug!(%id, "not closed at shutdown: {err}");
                }
            }
        };
        if tokio::time::timeout(CLOSE_TIMEOUT, drain).await.is_err() {
            tracing::warn!("shutdown: gave up closing some of {total} envs and batches");
        } else {
            tracing::info!("shutdown: closed {total} envs and batches");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_exactly_prefix_and_number() {
        assert_eq!(number("sim_12", ENV_PREFIX), Some(12));
        assert_eq!(number("sim_012", ENV_PREFIX), None);
        assert_eq!(number("sim_", ENV_PREFIX), None);
        assert_eq!(number("batch_3", ENV_PREFIX), None);
    }

    #[test]
    fn unknown_ids_list_the_open_ones() {
        let fleet = Fleet::new(vec!["127.0.0.1:1".into()], Client::builder(""));
        let err = fleet.env("sim_42").unwrap_err();
        assert!(matches!(
            err,
            McpError::UnknownId {
                kind: IdKind::Env,
                ..
            }
        ));
        assert_eq!(
            err.to_string(),
            "unknown env_id \"sim_42\": no open environment has this id (open: none). \
             Create one with create_robot_env."
        );
        assert!(fleet
            .batch("nope")
            .unwrap_err()
            .to_string()
            .starts_with("unknown batch_id \"nope\""));
        let many: Vec<String> = (1..=12).map(|n| format!("sim_{n}")).collect();
        assert_eq!(
            listing(many.iter()),
            "sim_1, sim_2, sim_3, sim_4, sim_5, sim_6, sim_7, sim_8, sim_9, sim_10, and 2 more"
        );
    }
}
