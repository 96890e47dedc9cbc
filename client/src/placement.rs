//! Where a fleet batch's envs go: a deterministic split of `n_envs` across servers in
//! proportion to their simulation threads (largest-remainder rounding), within each
//! server's limits. Pure arithmetic, so it is unit-tested without servers.

/// How many envs one server may still take, from its reported limits and load.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ServerCapacity {
    /// Simulation threads: the weight of the server's share.
    pub(crate) threads: u32,
    /// The most envs it accepts in this batch, if limited.
    pub(crate) cap: Option<usize>,
}

impl ServerCapacity {
    /// A server that takes no share: one that did not answer.
    pub(crate) const NONE: ServerCapacity = ServerCapacity {
        threads: 0,
        cap: Some(0),
    };

    /// The capacity a server reports: its threads, capped by its batch-size limit and by
    /// the room left under its env limit (limits of 0 mean none).
    pub(crate) fn from_info(info: &crate::ServerInfo) -> Self {
        let to_usize = |v: u64| usize::try_from(v).unwrap_or(usize::MAX);
        let batch_cap =
            (info.limits.max_batch_size != 0).then(|| to_usize(info.limits.max_batch_size));
        // With auth on, `envs` and `batch_envs` are the caller's own: exact for the
        // tenant quota, a lower bound of the server's load for `max_envs`.
        let held = info.envs.saturating_add(info.batch_envs);
        let room = |max: u64| (max != 0).then(|| to_usize(max.saturating_sub(held)));
        let cap = [
            batch_cap,
            room(info.limits.max_envs),
            room(info.limits.tenant_max_envs),
        ]
        .into_iter()
        .flatten()
        .min();
        ServerCapacity {
            threads: info.threads,
            cap,
        }
    }
}

/// Splits `n_envs` across servers in proportion to `threads`, never giving a server more
/// than its `cap`: what a capped server cannot take is split again among the others.
/// Each round uses largest-remainder rounding, ties going to the earlier server, so the
/// result depends only on the inputs. A server may get 0 envs.
pub(crate) fn split_by_capacity(
    n_envs: usize,
    servers: &[ServerCapacity],
) -> Result<Vec<usize>, String> {
    if servers.iter().all(|s| s.threads == 0) {
        return Err("no server reports any simulation threads".to_string());
    }
    let mut shares = vec![0usize; servers.len()];
    let mut active: Vec<usize> = (0..servers.len())
        .filter(|&i| servers[i].threads > 0 && servers[i].cap != Some(0))
        .collect();
    let mut left = n_envs;
    while left > 0 {
        if active.is_empty() {
            let room: usize = shares.iter().sum();
            return Err(format!(
                "the fleet has room for {room} more envs (threads and limits: {}), not {n_envs}",
                describe(servers)
            ));
        }
        let weights: Vec<u32> = active.iter().map(|&i| servers[i].threads).collect();
        let round = largest_remainder(left, &weights);
        let over: Vec<usize> = active
            .iter()
            .zip(&round)
            .filter(|&(&i, &share)| servers[i].cap.is_some_and(|cap| share > cap))
            .map(|(&i, _)| i)
            .collect();
        if over.is_empty() {
            for (&i, share) in active.iter().zip(round) {
                shares[i] = share;
            }
            break;
        }
        for i in over {
            let cap = servers[i].cap.unwrap_or(0);
            shares[i] = cap;
            left -= cap;
        }
        active.retain(|&i| shares[i] == 0);
    }
    Ok(shares)
}

/// `n` split in proportion to `weights` (not all zero): the floors, then one more to
/// each of the largest remainders, ties to the lower index.
fn largest_remainder(n: usize, weights: &[u32]) -> Vec<usize> {
    let total: u128 = weights.iter().map(|&w| u128::from(w)).sum();
    let n128 = n as u128;
    let mut shares: Vec<usize> = Vec::with_capacity(weights.len());
    let mut remainders: Vec<(u128, usize)> = Vec::with_capacity(weights.len());
    for (i, &w) in weights.iter().enumerate() {
        let exact = n128 * u128::from(w);
        // Each floor is at most n, so it fits.
        shares.push((exact / total) as usize);
        remainders.push((exact % total, i));
    }
    let extra = n - shares.iter().sum::<usize>();
    remainders.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
    for &(_, i) in remainders.iter().take(extra) {
        shares[i] += 1;
    }
    shares
}

fn describe(servers: &[ServerCapacity]) -> String {
    let parts: Vec<String> = servers
        .iter()
        .map(|s| match s.cap {
            Some(cap) => format!("{} threads, room {cap}", s.threads),
            None => format!("{} threads", s.threads),
        })
        .collect();
    parts.join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn threads(list: &[u32]) -> Vec<ServerCapacity> {
        list.iter()
            .map(|&threads| ServerCapacity { threads, cap: None })
            .collect()
    }

    #[test]
    fn shares_follow_thread_counts() {
        assert_eq!(
            split_by_capacity(96, &threads(&[1, 2, 3])),
            Ok(vec![16, 32, 48])
        );
        assert_eq!(split_by_capacity(10, &threads(&[4])), Ok(vec![10]));
        assert_eq!(
            split_by_capacity(8, &threads(&[2, 2, 2, 2])),
            Ok(vec![2; 4])
        );
    }

    #[test]
    fn remainders_go_to_the_largest_fractions_then_the_earlier_server() {
        // 10 × (1, 2, 3) / 6 = 1.67, 3.33, 5: the largest remainder is the first.
        assert_eq!(
            split_by_capacity(10, &threads(&[1, 2, 3])),
            Ok(vec![2, 3, 5])
        );
        // Equal weights and remainders: earlier servers first.
        assert_eq!(
            split_by_capacity(5, &threads(&[1, 1, 1])),
            Ok(vec![2, 2, 1])
        );
        // The sum is always exact.
        for n in 0..50 {
            let shares = split_by_capacity(n, &threads(&[3, 5, 7, 1])).unwrap();
            assert_eq!(shares.iter().sum::<usize>(), n);
        }
    }

    #[test]
    fn tiny_batches_leave_servers_empty() {
        assert_eq!(
            split_by_capacity(1, &threads(&[1, 2, 3])),
            Ok(vec![0, 0, 1])
        );
        assert_eq!(
            split_by_capacity(2, &threads(&[1, 2, 3])),
            Ok(vec![0, 1, 1])
        );
        assert_eq!(split_by_capacity(0, &threads(&[1, 2])), Ok(vec![0, 0]));
    }

    #[test]
    fn zero_capacity_servers_get_nothing_and_an_all_zero_fleet_is_an_error() {
        assert_eq!(
            split_by_capacity(6, &threads(&[0, 2, 1])),
            Ok(vec![0, 4, 2])
        );
        let err = split_by_capacity(6, &threads(&[0, 0])).unwrap_err();
        assert!(
            err.contains("no server reports any simulation threads"),
            "{err}"
        );
        assert!(split_by_capacity(6, &[]).is_err());
    }

    #[test]
    fn capped_servers_pass_the_rest_to_the_others() {
        let servers = [
            ServerCapacity {
                threads: 1,
                cap: None,
            },
            ServerCapacity {
                threads: 2,
                cap: Some(10),
            },
            ServerCapacity {
                threads: 3,
                cap: None,
            },
        ];
        // Uncapped: 16/32/48. Server 1 takes 10; 86 split 1:3 is 21.5/64.5.
        assert_eq!(split_by_capacity(96, &servers), Ok(vec![22, 10, 64]));
        let full = [
            ServerCapacity {
                threads: 1,
                cap: Some(3),
            },
            ServerCapacity {
                threads: 1,
                cap: Some(0),
            },
        ];
        assert_eq!(split_by_capacity(3, &full), Ok(vec![3, 0]));
        let err = split_by_capacity(4, &full).unwrap_err();
        assert!(err.contains("room for 3"), "{err}");
    }

    #[test]
    fn limits_become_caps() {
        let mut info = crate::ServerInfo {
            threads: 4,
            envs: 10,
            batch_envs: 80,
            ..Default::default()
        };
        assert_eq!(ServerCapacity::from_info(&info).cap, None);
        info.limits.max_envs = 100;
        assert_eq!(ServerCapacity::from_info(&info).cap, Some(10));
        info.limits.max_batch_size = 5;
        assert_eq!(ServerCapacity::from_info(&info).cap, Some(5));
        info.limits.max_envs = 50;
        assert_eq!(ServerCapacity::from_info(&info).cap, Some(0));
        info.limits.max_envs = 0;
        info.limits.tenant_max_envs = 93;
        assert_eq!(ServerCapacity::from_info(&info).cap, Some(3));
    }
}
