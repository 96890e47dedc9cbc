//! End-to-end tests: a real server on 127.0.0.1:0 (in-process, `gymfleet_server::serve`),
//! driven over the network by `gymfleet-client`. One test binary, one module per area.

mod adversarial;
mod batches;
mod contact_work;
mod dashboard;
mod errors;
mod fleet;
mod fleet_start;
mod fleet_subsets;
mod imports;
mod joint_state;
mod keyframes;
mod lifecycle;
mod probes;
mod reasons;
mod regressions;
mod render;
mod replay;
mod security;
mod states;
mod structure;
mod subset_steps;
mod tasks;
mod terms;
mod transport;
mod walkthrough;

use gymfleet_client::{ClientError, Fleet, FleetEndpoints};
use gymfleet_e2e::TestServer;
use gymfleet_server::ServerConfig;

/// A fleet of two servers, with 1 and 2 pool threads, for sharding a batch that must step
/// bitwise as it does on one server. Keep the servers alive as long as the fleet.
async fn two_server_fleet() -> (Vec<TestServer>, Fleet) {
    let mut servers = Vec::new();
    for threads in [1, 2] {
        servers.push(
            TestServer::start(ServerConfig {
                threads,
                ..ServerConfig::default()
            })
            .await,
        );
    }
    let endpoints =
        FleetEndpoints::new(servers.iter().map(|s| s.addr().to_string())).expect("endpoints");
    let fleet = Fleet::connect(endpoints).await.expect("fleet");
    (servers, fleet)
}

/// The message of a RESOURCE_EXHAUSTED refusal (panics on any other error).
fn exhausted(err: ClientError) -> String {
    match err {
        ClientError::ResourceExhausted { message, .. } => message,
        other => panic!("expected RESOURCE_EXHAUSTED, got {other:?}"),
    }
}

/// Asserts that `a` and `b` have the same length and agree within `tol`.
#[track_caller]
fn assert_close(a: &[f32], b: &[f32], tol: f32) {
    assert_eq!(a.len(), b.len(), "lengths differ: {a:?} vs {b:?}");
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= tol,
            "index {i}: {x} vs {y} (tol {tol}); {a:?} vs {b:?}"
        );
    }
}

/// The bit patterns of a float slice, for bitwise comparison.
fn bits(values: &[f32]) -> Vec<u32> {
    values.iter().map(|v| v.to_bits()).collect()
}

/// Asserts that `err` is NOT_FOUND and that its message contains every piece of `needles`.
#[track_caller]
fn assert_not_found(err: &ClientError, needles: &[&str]) {
    assert!(
        matches!(err, ClientError::NotFound { .. }),
        "expected NOT_FOUND, got {err:?}"
    );
    assert_mentions(err, needles);
}

/// Asserts that the error's message contains every piece of `needles`.
#[track_caller]
fn assert_mentions(err: &ClientError, needles: &[&str]) {
    for needle in needles {
        assert!(
            err.message().contains(needle),
            "message {:?} does not mention {needle:?}",
            err.message()
        );
    }
}

/// Deterministic pseudo-random actions in [-amplitude, amplitude].
fn actions(seed: u64, len: usize, amplitude: f32) -> Vec<f32> {
    let mut state = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
    (0..len)
        .map(|_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let unit = (state >> 40) as f32 / (1u64 << 24) as f32;
            (unit * 2.0 - 1.0) * amplitude
        })
        .collect()
}

/// Waits for the idle sweeper to sweep at a manual clock's present time
/// ([`gymfleet_server::Clock::swept`]); the minute's bound only turns a sweeper that
/// never runs (a bug) into a failure instead of a hang.
async fn swept(clock: &gymfleet_server::Clock) {
    tokio::time::timeout(std::time::Duration::from_secs(60), clock.swept())
        .await
        .expect("the idle sweeper swept after the clock moved");
}
