//! The gymfleet side of the peer benchmark (`bench/peer/peer_bench.py`): wall-clock
//! microseconds per env step of one model, single thread, with the same workload
//! definitions as the MuJoCo side (`bench/peer/mujoco_side.py`).
//!
//! ```text
//! cargo run --release -p gymfleet-env --example peer_step -- \
//!     --document models/arm6.json --end-effector tool --substeps 5 \
//!     --variant random --amplitudes 0.000845,0.23,0.0339,2.59e-05,0.00178,4.34e-06
//! ```
//!
//! Variants (torques in N·m, one per DOF, held for one env step):
//! - `zero`: zero torque from the initial pose;
//! - `tilt`: zero torque, each DOF offset by U(±`--tilt-deg`) at every reset (`reset_noise`);
//! - `sine`: `A_j·sin(2π·f_j·t + φ_j)`, `f_j` ∈ U(0.5, 1.5) Hz, `φ_j` ∈ U(0, 2π);
//! - `random`: U(−A_j, A_j) per env step.
//!
//! The env is reset every 1000 env steps, inside the timed loop. Prints one JSON object;
//! its `obs_hash` (of every observation of the last repeat) tells whether two builds step
//! the same trajectory bit for bit.
//!
//! `--envs N` steps N copies of the env in turn for each row of actions, as a batch shard
//! steps its envs (the time is then per env step, and includes fetching each env's state
//! back into the caches); `--prefetch on` hints each env's state in while the one before it
//! steps, as the batch's chunks do (`RobotEnv::prefetch`); `--order serpentine` steps them
//! last to first on every other row, so that the envs stepped last, still in the caches, come
//! first. The hash is the first env's.
//!
//! `--contact-limit N` gives the envs the server's contact-work limit (contact points ×
//! substeps per step, `--max-contact-work`; 0, the default: none, as `RobotEnv` has), so that
//! its per-step count is measured too.

use std::time::Instant;

use gymfleet_env::{ActionType, EnvConfig, RobotEnv};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

const RESET_EVERY: usize = 1000;

struct Args {
    document: String,
    end_effector: String,
    substeps: u32,
    dt: f64,
    steps: usize,
    repeats: usize,
    variant: String,
    amplitudes: Vec<f32>,
    tilt_deg: f64,
    envs: usize,
    prefetch: bool,
    serpentine: bool,
    contact_limit: usize,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        document: String::new(),
        end_effector: String::new(),
        substeps: gymfleet_env::DEFAULT_SUBSTEPS,
        dt: gymfleet_env::DEFAULT_DT,
        steps: 4000,
        repeats: 5,
        variant: "zero".to_string(),
        amplitudes: Vec::new(),
        tilt_deg: 0.01f64.to_degrees(),
        envs: 1,
        prefetch: false,
        serpentine: false,
        contact_limit: 0,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{flag} needs a value"));
        let bad = |e: &dyn std::fmt::Display| format!("{flag}: {e}");
        match flag.as_str() {
            "--document" => args.document = value()?,
            "--end-effector" => args.end_effector = value()?,
            "--substeps" => args.substeps = value()?.parse().map_err(|e| bad(&e))?,
            "--dt" => args.dt = value()?.parse().map_err(|e| bad(&e))?,
            "--steps" => args.steps = value()?.parse().map_err(|e| bad(&e))?,
            "--repeats" => args.repeats = value()?.parse().map_err(|e| bad(&e))?,
            "--variant" => args.variant = value()?,
            "--tilt-deg" => args.tilt_deg = value()?.parse().map_err(|e| bad(&e))?,
            "--envs" => args.envs = value()?.parse().map_err(|e| bad(&e))?,
            "--contact-limit" => args.contact_limit = value()?.parse().map_err(|e| bad(&e))?,
            "--prefetch" => {
                args.prefetch = match value()?.as_str() {
                    "on" => true,
                    "off" => false,
                    other => return Err(format!("--prefetch takes on or off, not {other:?}")),
                }
            }
            "--order" => {
                args.serpentine = match value()?.as_str() {
                    "serpentine" => true,
                    "forward" => false,
                    other => {
                        return Err(format!(
                            "--order takes forward or serpentine, not {other:?}"
                        ))
                    }
                }
            }
            "--amplitudes" => {
                args.amplitudes = value()?
                    .split(',')
                    .map(|a| a.trim().parse::<f32>().map_err(|e| bad(&e)))
                    .collect::<Result<_, _>>()?
            }
            other => return Err(format!("unknown flag {other}")),
        }
    }
    if args.document.is_empty() {
        return Err("--document is required".to_string());
    }
    Ok(args)
}

/// One row of torques per env step.
fn torque_table(args: &Args, dofs: usize) -> Result<Vec<Vec<f32>>, String> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(0);
    let amp = |j: usize| args.amplitudes.get(j).copied().unwrap_or(0.0);
    if matches!(args.variant.as_str(), "sine" | "random") && args.amplitudes.len() != dofs {
        return Err(format!(
            "--amplitudes: expected {dofs} values, got {}",
            args.amplitudes.len()
        ));
    }
    Ok(match args.variant.as_str() {
        "zero" | "tilt" => vec![vec![0.0; dofs]; args.steps],
        "random" => (0..args.steps)
            .map(|_| {
                (0..dofs)
                    .map(|j| amp(j) * rng.random_range(-1.0f32..1.0))
                    .collect()
            })
            .collect(),
        "sine" => {
            let f: Vec<f64> = (0..dofs).map(|_| rng.random_range(0.5..1.5)).collect();
            let phi: Vec<f64> = (0..dofs)
                .map(|_| rng.random_range(0.0..std::f64::consts::TAU))
                .collect();
            (0..args.steps)
                .map(|i| {
                    let t = (i % RESET_EVERY) as f64 * args.dt;
                    (0..dofs)
                        .map(|j| amp(j) * (std::f64::consts::TAU * f[j] * t + phi[j]).sin() as f32)
                        .collect()
                })
                .collect()
        }
        other => {
            return Err(format!(
                "--variant: expected zero, tilt, sine or random, got {other}"
            ))
        }
    })
}

fn main() {
    let args = parse_args().unwrap_or_else(|e| {
        eprintln!("peer_step: {e}");
        std::process::exit(2);
    });
    let document = std::fs::read_to_string(&args.document).unwrap_or_else(|e| {
        eprintln!("peer_step: {}: {e}", args.document);
        std::process::exit(2);
    });
    let config = EnvConfig {
        dt: args.dt,
        substeps: args.substeps,
        seed: 1,
        reset_noise: if args.variant == "tilt" {
            args.tilt_deg
        } else {
            0.0
        },
        ..EnvConfig::with_end_effectors([args.end_effector.clone()])
    };
    let mut envs = (0..args.envs.max(1))
        .map(|_| RobotEnv::from_json(&document, config.clone()))
        .collect::<Result<Vec<_>, _>>()
        .unwrap_or_else(|e| {
            eprintln!("peer_step: {e}");
            std::process::exit(2);
        });
    for env in &mut envs {
        env.set_contact_work_limit(args.contact_limit);
    }
    let dofs = envs[0].spec().action_dim;
    let table = torque_table(&args, dofs).unwrap_or_else(|e| {
        eprintln!("peer_step: {e}");
        std::process::exit(2);
    });
    let mut obs = vec![0.0f32; envs[0].spec().observation_dim];
    let mut diverged = 0usize;
    // FNV-1a over the bits of every observation of the first env in the last repeat: two
    // builds that print the same hash stepped the same trajectory bit for bit.
    let mut obs_hash = 0u64;
    // With `--envs N`, each row steps N envs one after the other (the same actions, their
    // own state), as a batch shard steps its envs: the time per env step then includes
    // fetching each env's state from wherever the other N - 1 left it in the caches.
    let mut run = |rows: &[Vec<f32>]| {
        obs_hash = 0xcbf2_9ce4_8422_2325;
        let start = Instant::now();
        for (i, action) in rows.iter().enumerate() {
            let n = envs.len();
            let backward = args.serpentine && i % 2 == 1;
            for j in 0..n {
                let k = if backward { n - 1 - j } else { j };
                if args.prefetch && j + 1 < n {
                    envs[if backward { k - 1 } else { k + 1 }].prefetch();
                }
                let env = &mut envs[k];
                if i % RESET_EVERY == 0 {
                    env.reset_into(None, &mut obs);
                }
                let flags = env
                    .step_into(ActionType::Torque, action, &mut obs)
                    .expect("a valid action, within --contact-limit");
                if flags.terminated {
                    diverged += 1;
                    env.reset_into(None, &mut obs);
                }
                if k == 0 {
                    for x in &obs {
                        obs_hash =
                            (obs_hash ^ u64::from(x.to_bits())).wrapping_mul(0x0100_0000_01b3);
                    }
                }
            }
        }
        start.elapsed().as_secs_f64() / (rows.len() * envs.len()) as f64 * 1e6
    };
    run(&table[..table.len().min(200)]); // warm-up
    let mut us: Vec<f64> = (0..args.repeats).map(|_| run(&table)).collect();
    let repeats = us.clone();
    us.sort_by(f64::total_cmp);
    let median = us[us.len() / 2];
    println!(
        "{{\"document\": {:?}, \"variant\": {:?}, \"substeps\": {}, \"dofs\": {dofs}, \
         \"us_per_env_step\": {median:.3}, \"repeats_us\": {repeats:?}, \"diverged\": {diverged}, \
         \"envs\": {}, \"obs_hash\": \"{obs_hash:016x}\"}}",
        args.document, args.variant, args.substeps, args.envs
    );
}
