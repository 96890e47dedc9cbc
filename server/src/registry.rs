//! The open environments and batches: ids, owners, per-entry async locks, idle times,
//! and the env-count limits (the server's and each tenant's).
//!
//! Each entry sits behind its own `tokio::sync::Mutex`, so calls on one env serialise
//! while calls on different envs run in parallel. The mutex holds an `Option`: `None`
//! means the entry was closed (by `Close`, the idle sweeper, or a panic) while a call was
//! queued on it, and that call answers NOT_FOUND.
//!
//! Each entry also has an [`Activity`]: counters its step jobs add to with atomics (no
//! lock on the step path), which the dashboard reads without taking the entry's lock.

use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use tokio::sync::OwnedMutexGuard;

use crate::clock::Clock;
use crate::tenant::Tenant;

use crate::error::{EntityKind, Result, ServerError};
use crate::limit::Limit;

mod activity;
pub(crate) use activity::{clear_done, Activity, Facts, Rates};

/// Counts held environments against `--max-envs` (the server's capacity) or against
/// `--tenant-max-envs` (one tenant's).
#[derive(Debug)]
pub(crate) struct EnvCapacity {
    max: usize,
    /// `None` for the server's capacity, the tenant for a tenant's quota.
    tenant: Option<Tenant>,
    held: AtomicUsize,
    batch_envs: AtomicUsize,
}

impl EnvCapacity {
    /// The server's capacity.
    pub(crate) fn new(max: usize) -> Arc<Self> {
        Self::with_owner(max, None)
    }

    /// A tenant's quota.
    pub(crate) fn for_tenant(max: usize, tenant: Tenant) -> Arc<Self> {
        Self::with_owner(max, Some(tenant))
    }

    fn with_owner(max: usize, tenant: Option<Tenant>) -> Arc<Self> {
        Arc::new(EnvCapacity {
            max,
            tenant,
            held: AtomicUsize::new(0),
            batch_envs: AtomicUsize::new(0),
        })
    }

    /// Reserves `n` environments, or refuses with RESOURCE_EXHAUSTED. The reservation is
    /// released when the returned value is dropped, so a failed creation frees it.
    pub(crate) fn reserve(self: &Arc<Self>, n: usize, kind: EntityKind) -> Result<Reservation> {
        let mut held = self.held.load(Ordering::Relaxed);
        loop {
            let next = held.saturating_add(n);
            if Limit::exceeded(self.max, next) {
                return Err(match &self.tenant {
                    None => ServerError::TooManyEnvs {
                        requested: n,
                        held,
                        max: self.max,
                    },
                    Some(tenant) => ServerError::TenantQuota {
                        tenant: tenant.clone(),
                        requested: n,
                        held,
                        max: self.max,
                    },
                });
            }
            match self
                .held
                .compare_exchange_weak(held, next, Ordering::AcqRel, Ordering::Relaxed)
            {
                Ok(_) => break,
                Err(actual) => held = actual,
            }
        }
        if kind == EntityKind::Batch {
            self.batch_envs.fetch_add(n, Ordering::Relaxed);
        }
        Ok(Reservation {
            capacity: Arc::clone(self),
            n,
            kind,
            also: None,
        })
    }

    /// Reserves `n` environments here and then in `outer` (the tenant's quota, then the
    /// server's capacity); both or neither.
    pub(crate) fn reserve_within(
        self: &Arc<Self>,
        outer: &Arc<EnvCapacity>,
        n: usize,
        kind: EntityKind,
    ) -> Result<Reservation> {
        let mut inner = self.reserve(n, kind)?;
        inner.also = Some(Box::new(outer.reserve(n, kind)?));
        Ok(inner)
    }

    /// Environments held.
    #[cfg(test)]
    pub(crate) fn held(&self) -> usize {
        self.held.load(Ordering::Relaxed)
    }

    /// Environments held in batches.
    pub(crate) fn batch_envs(&self) -> usize {
        self.batch_envs.load(Ordering::Relaxed)
    }
}

/// `n` environments counted against the limit until dropped.
#[derive(Debug)]
pub(crate) struct Reservation {
    capacity: Arc<EnvCapacity>,
    n: usize,
    kind: EntityKind,
    /// The same environments reserved in an enclosing capacity, released together.
    also: Option<Box<Reservation>>,
}

impl Drop for Reservation {
    fn drop(&mut self) {
        self.capacity.held.fetch_sub(self.n, Ordering::AcqRel);
        if self.kind == EntityKind::Batch {
            self.capacity
                .batch_envs
                .fetch_sub(self.n, Ordering::Relaxed);
        }
    }
}

/// An open value with the capacity it holds.
#[derive(Debug)]
pub(crate) struct Held<T> {
    pub(crate) value: T,
    _reservation: Reservation,
}

impl<T> Held<T> {
    /// Releases the capacity now and returns the value, so that freeing it can happen
    /// elsewhere without a later create seeing the capacity still held.
    pub(crate) fn release(self) -> T {
        let Held {
            value,
            _reservation,
        } = self;
        drop(_reservation);
        value
    }
}

/// An entry as the dashboard lists it: read without its lock, and without marking it used.
#[derive(Debug, Clone)]
pub(crate) struct Watched {
    pub(crate) id: String,
    pub(crate) activity: Arc<Activity>,
    pub(crate) idle: Duration,
}

/// The lock guard of an entry: `None` once closed.
pub(crate) type Slot<T> = OwnedMutexGuard<Option<Held<T>>>;

/// One open env or batch.
#[derive(Debug)]
pub(crate) struct Entry<T> {
    id: String,
    /// The tenant that created it: the only one that can see it.
    owner: Tenant,
    slot: Arc<tokio::sync::Mutex<Option<Held<T>>>>,
    /// Milliseconds on the registry's clock at the last call.
    last_used_ms: AtomicU64,
    clock: Clock,
    activity: Arc<Activity>,
}

impl<T> Entry<T> {
    pub(crate) fn id(&self) -> &str {
        &self.id
    }

    /// Marks the entry as used now.
    pub(crate) fn touch(&self) {
        self.last_used_ms
            .store(millis(&self.clock), Ordering::Relaxed);
    }

    fn idle_for(&self) -> Duration {
        let last = self.last_used_ms.load(Ordering::Relaxed);
        Duration::from_millis(millis(&self.clock).saturating_sub(last))
    }

    /// Waits for the entry's lock; NOT_FOUND if it was closed meanwhile.
    pub(crate) async fn lock(&self, kind: EntityKind) -> Result<Slot<T>> {
        let guard = Arc::clone(&self.slot).lock_owned().await;
        if guard.is_none() {
            return Err(ServerError::NotFound {
                kind,
                id: self.id.clone(),
            });
        }
        Ok(guard)
    }
}

fn millis(clock: &Clock) -> u64 {
    u64::try_from(clock.elapsed().as_millis()).unwrap_or(u64::MAX)
}

/// The open values of one kind, by id.
#[derive(Debug)]
pub(crate) struct Registry<T> {
    kind: EntityKind,
    prefix: &'static str,
    next_id: AtomicU64,
    clock: Clock,
    entries: Mutex<HashMap<String, Arc<Entry<T>>>>,
}

impl<T> Registry<T> {
    /// A registry whose ids are `"<prefix>_<n>"`, n counting from 1, and whose idle times
    /// are measured on `clock`.
    pub(crate) fn new(kind: EntityKind, prefix: &'static str, clock: Clock) -> Self {
        Registry {
            kind,
            prefix,
            next_id: AtomicU64::new(1),
            clock,
            entries: Mutex::new(HashMap::new()),
        }
    }

    fn map(&self) -> std::sync::MutexGuard<'_, HashMap<String, Arc<Entry<T>>>> {
        // The map is only ever inserted into and removed from; a panic while it was locked
        // cannot leave it half-updated, so a poisoned lock is still usable.
        self.entries.lock().unwrap_or_else(PoisonError::into_inner)
    }

    pub(crate) fn kind(&self) -> EntityKind {
        self.kind
    }

    /// Adds a value owned by `owner` and returns its new id.
    #[cfg(test)]
    pub(crate) fn insert(&self, owner: &Tenant, value: T, reservation: Reservation) -> String {
        self.insert_with(owner, value, reservation, Activity::new(Facts::default()))
    }

    /// Adds a value owned by `owner`, whose step jobs count in `activity`, and returns
    /// its new id.
    pub(crate) fn insert_with(
        &self,
        owner: &Tenant,
        value: T,
        reservation: Reservation,
        activity: Arc<Activity>,
    ) -> String {
        let id = format!(
            "{}_{}",
            self.prefix,
            self.next_id.fetch_add(1, Ordering::Relaxed)
        );
        let entry = Arc::new(Entry {
            id: id.clone(),
            owner: owner.clone(),
            slot: Arc::new(tokio::sync::Mutex::new(Some(Held {
                value,
                _reservation: reservation,
            }))),
            last_used_ms: AtomicU64::new(millis(&self.clock)),
            clock: self.clock.clone(),
            activity,
        });
        self.map().insert(id.clone(), entry);
        id
    }

    /// Looks up an id of `owner`'s and marks it used; NOT_FOUND names the id. Another
    /// tenant's id is NOT_FOUND too, with the same message as an id that never existed.
    pub(crate) fn get(&self, owner: &Tenant, id: &str) -> Result<Arc<Entry<T>>> {
        let entry = self.peek(owner, id)?;
        entry.touch();
        Ok(entry)
    }

    /// Looks up an id of `owner`'s without marking it used (watching is not using: the
    /// dashboard must not keep an abandoned env from being reclaimed).
    pub(crate) fn peek(&self, owner: &Tenant, id: &str) -> Result<Arc<Entry<T>>> {
        self.map()
            .get(id)
            .filter(|entry| entry.owner == *owner)
            .cloned()
            .ok_or_else(|| ServerError::NotFound {
                kind: self.kind,
                id: id.to_string(),
            })
    }

    /// `owner`'s entries in id order (`sim_2` before `sim_10`), at most `limit` of them,
    /// and how many `owner` has; none is marked used.
    pub(crate) fn watch(&self, owner: &Tenant, limit: usize) -> (usize, Vec<Watched>) {
        let mut mine: Vec<Watched> = self
            .map()
            .values()
            .filter(|e| e.owner == *owner)
            .map(|e| Watched {
                id: e.id.clone(),
                activity: Arc::clone(&e.activity),
                idle: e.idle_for(),
            })
            .collect();
        mine.sort_by(|a, b| (a.id.len(), &a.id).cmp(&(b.id.len(), &b.id)));
        let total = mine.len();
        mine.truncate(limit);
        (total, mine)
    }

    /// Forgets an id. Calls already queued on its lock find the slot empty once the
    /// caller has taken the value out.
    pub(crate) fn remove(&self, id: &str) {
        self.map().remove(id);
    }

    /// Number of open values owned by `owner`.
    pub(crate) fn len_of(&self, owner: &Tenant) -> usize {
        self.map().values().filter(|e| e.owner == *owner).count()
    }

    /// Number of open values per owner.
    pub(crate) fn count_by_owner(&self) -> HashMap<Tenant, usize> {
        let mut counts = HashMap::new();
        for entry in self.map().values() {
            *counts.entry(entry.owner.clone()).or_default() += 1;
        }
        counts
    }

    /// Takes out every value idle for at least `ttl` and not in use right now, and
    /// returns them with their ids and idle times (to be dropped off the async runtime).
    pub(crate) fn take_idle(&self, ttl: Duration) -> Vec<(String, Duration, Held<T>)> {
        let candidates: Vec<Arc<Entry<T>>> = self
            .map()
            .values()
            .filter(|e| e.idle_for() >= ttl)
            .cloned()
            .collect();
        let mut reclaimed = Vec::new();
        for entry in candidates {
            // An entry whose lock is held is in use: not idle.
            let Ok(mut guard) = Arc::clone(&entry.slot).try_lock_owned() else {
                continue;
            };
            // Re-check under the lock: a call may have looked it up since.
            let idle = entry.idle_for();
            if idle < ttl {
                continue;
            }
            if let Some(held) = guard.take() {
                self.remove(&entry.id);
                reclaimed.push((entry.id.clone(), idle, held));
            }
        }
        reclaimed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reservations_count_against_the_limit_until_dropped() {
        let capacity = EnvCapacity::new(5);
        let a = capacity.reserve(3, EntityKind::Batch).unwrap();
        assert_eq!(capacity.batch_envs(), 3);
        let err = capacity.reserve(3, EntityKind::Env).unwrap_err();
        assert!(matches!(
            err,
            ServerError::TooManyEnvs {
                requested: 3,
                held: 3,
                max: 5
            }
        ));
        let b = capacity.reserve(2, EntityKind::Env).unwrap();
        drop(a);
        assert_eq!(capacity.batch_envs(), 0);
        let _c = capacity.reserve(3, EntityKind::Env).unwrap();
        drop(b);
        assert!(EnvCapacity::new(0)
            .reserve(usize::MAX, EntityKind::Env)
            .is_ok());
    }

    #[tokio::test]
    async fn ids_count_up_and_closed_entries_are_not_found() {
        let capacity = EnvCapacity::new(0);
        let registry = Registry::new(EntityKind::Env, "sim", Clock::manual());
        let anon = Tenant::anonymous();
        let first = registry.insert(&anon, 1u8, capacity.reserve(1, EntityKind::Env).unwrap());
        let second = registry.insert(&anon, 2u8, capacity.reserve(1, EntityKind::Env).unwrap());
        assert_eq!((first.as_str(), second.as_str()), ("sim_1", "sim_2"));
        assert_eq!(registry.len_of(&anon), 2);

        let entry = registry.get(&anon, &first).unwrap();
        let mut slot = entry.lock(EntityKind::Env).await.unwrap();
        assert_eq!(slot.as_ref().map(|h| h.value), Some(1));
        slot.take();
        registry.remove(&first);
        drop(slot);
        assert!(matches!(
            entry.lock(EntityKind::Env).await,
            Err(ServerError::NotFound { .. })
        ));
        assert!(matches!(
            registry.get(&anon, &first),
            Err(ServerError::NotFound { .. })
        ));
    }

    #[tokio::test]
    async fn idle_sweep_skips_entries_in_use() {
        let capacity = EnvCapacity::new(0);
        let registry = Registry::new(EntityKind::Batch, "batch", Clock::manual());
        let anon = Tenant::anonymous();
        let busy = registry.insert(&anon, (), capacity.reserve(1, EntityKind::Batch).unwrap());
        let idle = registry.insert(&anon, (), capacity.reserve(1, EntityKind::Batch).unwrap());
        let entry = registry.get(&anon, &busy).unwrap();
        let _guard = entry.lock(EntityKind::Batch).await.unwrap();
        let reclaimed = registry.take_idle(Duration::ZERO);
        let ids: Vec<&str> = reclaimed.iter().map(|(id, _, _)| id.as_str()).collect();
        assert_eq!(ids, [idle.as_str()]);
        assert_eq!(registry.len_of(&anon), 1);
        assert!(registry.take_idle(Duration::from_secs(3600)).is_empty());
    }

    #[test]
    fn watching_lists_an_owners_entries_in_id_order_without_using_them() {
        let capacity = EnvCapacity::new(0);
        let clock = Clock::manual();
        let registry = Registry::new(EntityKind::Env, "sim", clock.clone());
        let (a, b) = (Tenant::named("a"), Tenant::named("b"));
        let mut ids = Vec::new();
        for i in 0..11 {
            let owner = if i == 3 { &b } else { &a };
            let held = capacity.reserve(1, EntityKind::Env).unwrap();
            ids.push(registry.insert(owner, (), held));
        }
        clock.advance(Duration::from_secs(5));
        let (total, first) = registry.watch(&a, 9);
        assert_eq!(total, 10);
        let listed: Vec<&str> = first.iter().map(|w| w.id.as_str()).collect();
        assert_eq!(
            listed,
            ["sim_1", "sim_2", "sim_3", "sim_5", "sim_6", "sim_7", "sim_8", "sim_9", "sim_10"]
        );
        assert_eq!(first[0].idle, Duration::from_secs(5));
        assert!(registry.peek(&a, &ids[0]).is_ok());
        assert!(matches!(
            registry.peek(&a, &ids[3]),
            Err(ServerError::NotFound { .. })
        ));
        // Neither watching nor peeking marked anything used: all of them are idle.
        assert_eq!(registry.take_idle(Duration::from_secs(5)).len(), 11);
    }

    #[tokio::test]
    async fn another_tenants_id_is_not_found_and_quotas_are_per_tenant() {
        let server = EnvCapacity::new(10);
        let (a, b) = (Tenant::named("a"), Tenant::named("b"));
        let (quota_a, quota_b) = (
            EnvCapacity::for_tenant(4, a.clone()),
            EnvCapacity::for_tenant(4, b.clone()),
        );
        let registry = Registry::new(EntityKind::Env, "sim", Clock::manual());
        let id = registry.insert(
            &a,
            (),
            quota_a.reserve_within(&server, 3, EntityKind::Env).unwrap(),
        );
        assert!(registry.get(&a, &id).is_ok());
        let mine = registry.get(&b, &id).unwrap_err().to_string();
        let none = registry.get(&b, "sim_999").unwrap_err().to_string();
        assert_eq!(mine.replace(&id, "X"), none.replace("sim_999", "X"));
        assert_eq!((registry.len_of(&a), registry.len_of(&b)), (1, 0));

        let err = quota_a
            .reserve_within(&server, 2, EntityKind::Env)
            .unwrap_err();
        assert!(matches!(
            err,
            ServerError::TenantQuota {
                requested: 2,
                held: 3,
                max: 4,
                ..
            }
        ));
        assert_eq!(server.held(), 3, "a refused quota reserves nothing");
        // b's quota is its own; the server's capacity is shared.
        let b_held = quota_b.reserve_within(&server, 4, EntityKind::Env).unwrap();
        let err = EnvCapacity::for_tenant(0, Tenant::named("c"))
            .reserve_within(&server, 4, EntityKind::Env)
            .unwrap_err();
        assert!(matches!(err, ServerError::TooManyEnvs { held: 7, .. }));
        drop(b_held);
        assert_eq!((quota_b.held(), server.held()), (0, 3));
    }
}
