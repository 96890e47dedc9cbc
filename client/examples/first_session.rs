//! A first session against a running server: the seed's pendulum, then a batch of arms.
//!
//! ```sh
//! cargo run --release -p gymfleet-server &          # listens on 127.0.0.1:50051
//! cargo run --release -p gymfleet-client --example first_session [ADDR]
//! ```

use std::process::ExitCode;

use gymfleet_client::{
    cannot_connect, ActionType, BatchOptions, Camera, CameraPreset, Client, ClientError, EnvOptions,
};

const PENDULUM: &str = include_str!("../../models/pendulum.json");
const ARM2: &str = include_str!("../../models/arm2.json");

#[tokio::main(flavor = "current_thread")]
async fn main() -> ExitCode {
    let addr = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "127.0.0.1:50051".into());
    match session(addr).await {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            // Errors are printed for people (Display), the unreachable server with how to
            // point this program elsewhere.
            match err.downcast_ref::<ClientError>() {
                Some(ClientError::Connect { addr, reason }) => eprintln!(
                    "error: {}",
                    cannot_connect(
                        addr,
                        reason,
                        "give its address as the argument: first_session ADDR"
                    )
                ),
                _ => eprintln!("error: {err}"),
            }
            ExitCode::FAILURE
        }
    }
}

async fn session(addr: String) -> Result<(), Box<dyn std::error::Error>> {
    let client = Client::connect(addr).await?;
    let server = client.server_info().await?;
    println!("server {} with {} threads", server.version, server.threads);

    // One environment: the seed's pendulum, which starts upright and falls. The pose of an
    // end effector is its centre of mass: the arm's middle, not its tip.
    let env = client
        .create_env(EnvOptions::new(PENDULUM).end_effectors(["arm"]))
        .await?;
    let info = env.info();
    println!(
        "{}: {} joint(s), action_dim {}, observation_dim {}",
        info.env_id, info.num_joints, info.action_dim, info.observation_dim
    );
    let first = env.reset(None).await?;
    println!("reset: pose {:?}", first.end_effector_poses[0]);
    // The seed pendulum's arm weighs 0.64 g: 1e-4 N·m for one step (1/240 s) is a push.
    let pushed = env.step(ActionType::Torque, &[1e-4]).await?;
    println!("pushed: {:.3} deg", pushed.observation.joint_positions[0]);
    for _ in 0..59 {
        env.step(ActionType::Torque, &[0.0]).await?; // free swing
    }
    let now = env.observe().await?;
    println!(
        "after 0.25 s: {:.2} deg at {:.2} deg/s",
        now.joint_positions[0], now.joint_velocities[0]
    );
    // A picture of it, from the front: a PNG, written under target/ (cargo's build folder,
    // which git ignores) rather than into the repository.
    let picture = env
        .render(&Camera::preset(CameraPreset::Front), 0, 0)
        .await?;
    let path = std::path::Path::new("target").join("pendulum.png");
    std::fs::create_dir_all("target")?;
    std::fs::write(&path, &picture.png)?;
    println!("{}: {}", path.display(), picture.description);
    env.close().await?;

    // A batch of 16 two-joint arms: actions are n_envs × action_dim floats, row-major.
    let batch = client
        .create_batch(
            BatchOptions::new(ARM2, 16)
                .end_effectors(["forearm"])
                .seed(7),
        )
        .await?;
    let (n, dim) = (batch.info().n_envs, batch.info().action_dim);
    batch.reset(Some(7)).await?;
    // Position targets in degrees: shoulder +20, elbow -30 (its limits are -120..0).
    let targets: Vec<f32> = [20.0, -30.0].into_iter().cycle().take(n * dim).collect();
    let mut last = None;
    for _ in 0..240 {
        last = Some(batch.step(ActionType::Position, &targets).await?); // deg
    }
    let step = last.expect("stepped");
    println!(
        "env 0 after 1 s of position control: {:?}",
        &step.obs(0)[..dim]
    );
    batch.close().await?;
    Ok(())
}
