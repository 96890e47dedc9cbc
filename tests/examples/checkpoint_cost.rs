//! What fleet checkpoints cost (BENCHMARKS.md J2): a fleet batch of arm2 envs sharded over
//! two in-process servers, stepped with and without `checkpoint_every(K)`, alternating the
//! two for several rounds; prints env-steps/s of each and the ratio, plus what one
//! checkpoint holds.
//!
//! ```sh
//! cargo run --release -p gymfleet-e2e --example checkpoint_cost -- [ENVS] [K] [STEPS] [ROUNDS]
//! ```
//!
//! Defaults: 256 envs, K = 100, 1000 steps per run, 5 rounds; each server has one pool
//! thread (two servers on the 2-core VM).

use std::time::Instant;

use gymfleet_client::{ActionType, BatchOptions, Fleet, FleetEndpoints};
use gymfleet_e2e::ARM2;
use gymfleet_server::{LocalServer, ServerConfig};

async fn run(fleet: &Fleet, envs: usize, every: u64, steps: usize) -> (f64, Option<usize>) {
    let mut batch = fleet
        .create_batch(BatchOptions::new(ARM2, envs).seed(1).max_steps(200))
        .await
        .expect("fleet batch");
    batch.reset(Some(1)).await.expect("reset");
    if every > 0 {
        batch.checkpoint_every(every).await.expect("checkpoint");
    }
    let actions: Vec<f32> = (0..envs * 2)
        .map(|k| 0.01 * ((k % 7) as f32 - 3.0))
        .collect();
    let start = Instant::now();
    for _ in 0..steps {
        batch
            .step(ActionType::Torque, &actions)
            .await
            .expect("step");
    }
    let rate = (steps * envs) as f64 / start.elapsed().as_secs_f64();
    let bytes = batch.checkpoint_status().map(|s| s.bytes);
    batch.close().await.expect("close");
    (rate, bytes)
}

fn main() {
    let mut args = std::env::args().skip(1);
    let envs: usize = args.next().map_or(256, |a| a.parse().expect("ENVS"));
    let every: u64 = args.next().map_or(100, |a| a.parse().expect("K"));
    let steps: usize = args.next().map_or(1000, |a| a.parse().expect("STEPS"));
    let rounds: usize = args.next().map_or(5, |a| a.parse().expect("ROUNDS"));
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("runtime");
    runtime.block_on(async move {
        let config = || ServerConfig {
            threads: 1,
            ..ServerConfig::default()
        };
        let a = LocalServer::start(config()).await.expect("server a");
        let b = LocalServer::start(config()).await.expect("server b");
        let endpoints =
            FleetEndpoints::new([a.client_addr(), b.client_addr()]).expect("two endpoints");
        let fleet = Fleet::connect(endpoints).await.expect("fleet");
        run(&fleet, envs, 0, steps / 10).await; // warm up
        let (mut plain, mut checkpointed) = (Vec::new(), Vec::new());
        let mut bytes = 0;
        for _ in 0..rounds {
            plain.push(run(&fleet, envs, 0, steps).await.0);
            let (rate, size) = run(&fleet, envs, every, steps).await;
            checkpointed.push(rate);
            bytes = size.unwrap_or(0);
        }
        let median = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let (p, c) = (median(&mut plain), median(&mut checkpointed));
        println!(
            "{envs} arm2 envs on 2 servers x 1 thread, {steps} steps per run, median of {rounds}"
        );
        println!("without checkpoints:      {p:>9.0} env-steps/s");
        println!("checkpoint every {every:>4}:    {c:>9.0} env-steps/s");
        println!(
            "ratio: {:.3} (cost {:.1} %); one checkpoint: {bytes} bytes ({} per env)",
            c / p,
            100.0 * (1.0 - c / p),
            bytes / envs.max(1)
        );
        a.stop().await.expect("stop");
        b.stop().await.expect("stop");
    });
}
