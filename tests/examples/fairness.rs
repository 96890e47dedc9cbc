//! Fairness between tenants (BENCHMARKS.md I1): one tenant's single-env `Step` latency on
//! an idle server, then while another tenant steps 16 384-env batches back to back on
//! the same pool. Prints p50/p99/max of both phases and the loaded/idle p99 ratio.
//!
//! ```sh
//! cargo run --release -p gymfleet-e2e --example fairness -- [THREADS] [SECONDS] [BIG_ENVS] [NICENESS]
//! ```
//!
//! Defaults: 2 pool threads, 10 s per phase, 16 384 envs, the pool at niceness 10
//! (`--pool-niceness`, `FAIR_POOL_NICENESS`: the setting this measures; 0 is the server's
//! default). Both tenants reach the server
//! over loopback gRPC with their own tokens, as two trainers on a shared server would.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use gymfleet_client::{ActionType, BatchOptions, Client, EnvOptions};
use gymfleet_e2e::{ARM2, PENDULUM};
use gymfleet_server::{LocalServer, ServerConfig, TokenTable};
use hdrhistogram::Histogram;

const SMALL: &str = "small-tenant-token-0123456789";
const BIG: &str = "big-tenant-token-0123456789";

/// Steps one pendulum for `seconds` and returns its Step latencies, in µs.
async fn single_env_latency(client: &Client, seconds: f64) -> Histogram<u64> {
    let env = client
        .create_env(EnvOptions::new(PENDULUM))
        .await
        .expect("small tenant's env");
    env.reset(Some(0)).await.expect("reset");
    let mut histogram = Histogram::<u64>::new(3).expect("histogram");
    let until = Instant::now() + Duration::from_secs_f64(seconds);
    let mut torque = 0.5_f32;
    while Instant::now() < until {
        let start = Instant::now();
        let step = env.step(ActionType::Torque, &[torque]).await.expect("step");
        let micros = u64::try_from(start.elapsed().as_micros()).unwrap_or(u64::MAX);
        histogram.record(micros.max(1)).expect("record");
        if step.done {
            env.reset(None).await.expect("reset");
        }
        torque = -torque;
    }
    env.close().await.expect("close");
    histogram
}

fn line(name: &str, h: &Histogram<u64>) -> String {
    format!(
        "{name:<28} steps {:>7}  p50 {:>7} µs  p99 {:>7} µs  max {:>8} µs",
        h.len(),
        h.value_at_quantile(0.5),
        h.value_at_quantile(0.99),
        h.max()
    )
}

fn main() {
    let mut args = std::env::args().skip(1);
    let threads: usize = args.next().map_or(2, |a| a.parse().expect("THREADS"));
    let seconds: f64 = args.next().map_or(10.0, |a| a.parse().expect("SECONDS"));
    let big_envs: usize = args.next().map_or(16_384, |a| a.parse().expect("BIG_ENVS"));
    let pool_niceness: u8 = args.next().map_or(gymfleet_batch::FAIR_POOL_NICENESS, |a| {
        a.parse().expect("NICENESS")
    });
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("runtime");
    runtime.block_on(async move {
        let tokens = TokenTable::parse(&format!("small {SMALL}\nbig {BIG}\n")).expect("tokens");
        let server = LocalServer::start(ServerConfig {
            threads,
            pool_niceness,
            auth_tokens: Some(Arc::new(tokens)),
            ..ServerConfig::default()
        })
        .await
        .expect("server");
        let addr = server.client_addr();
        let small = Client::builder(addr.clone())
            .token(SMALL)
            .connect()
            .await
            .expect("small tenant");
        let big = Client::builder(addr)
            .token(BIG)
            .connect()
            .await
            .expect("big tenant");
        println!("server: {threads} pool threads; big tenant: {big_envs} arm2 envs per batch step");

        // Warm up, then the idle phase.
        single_env_latency(&small, 1.0).await;
        let idle = single_env_latency(&small, seconds).await;

        let batch = big
            .create_batch(BatchOptions::new(ARM2, big_envs))
            .await
            .expect("big tenant's batch");
        batch.reset(Some(1)).await.expect("reset");
        let stop = Arc::new(AtomicBool::new(false));
        let big_steps = Arc::new(AtomicU64::new(0));
        let stepping = {
            let (stop, big_steps) = (Arc::clone(&stop), Arc::clone(&big_steps));
            let actions = vec![0.1_f32; big_envs * 2];
            tokio::spawn(async move {
                while !stop.load(Ordering::Relaxed) {
                    batch
                        .step(ActionType::Torque, &actions)
                        .await
                        .expect("big step");
                    big_steps.fetch_add(1, Ordering::Relaxed);
                }
                batch.close().await.expect("close");
            })
        };
        // Let the big tenant's steps start before measuring.
        while big_steps.load(Ordering::Relaxed) == 0 {
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
        let started = Instant::now();
        let before = big_steps.load(Ordering::Relaxed);
        let loaded = single_env_latency(&small, seconds).await;
        let big_rate = (big_steps.load(Ordering::Relaxed) - before) as f64 * big_envs as f64
            / started.elapsed().as_secs_f64();
        stop.store(true, Ordering::Relaxed);
        stepping.await.expect("big tenant's task");

        println!("{}", line("small tenant, idle server", &idle));
        println!("{}", line("small tenant, big tenant on", &loaded));
        println!("big tenant meanwhile: {big_rate:.0} env-steps/s");
        println!(
            "p99 loaded / idle = {:.2}",
            loaded.value_at_quantile(0.99) as f64 / idle.value_at_quantile(0.99) as f64
        );
        server.stop().await.expect("stop");
    });
}
