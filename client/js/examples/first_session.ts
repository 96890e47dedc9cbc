// A first session against a running server: the seed's pendulum, then a batch of arms.
// The TypeScript twin of client/examples/first_session.rs, with the same numbers.
//
//   cargo run --release -p gymfleet-server &     # listens on 127.0.0.1:50051
//   cd client/js && npm ci && npm run build
//   node dist/examples/first_session.js [ADDR]    # default: GYMFLEET_SERVER, else 127.0.0.1:50051

import { mkdirSync, readFileSync, writeFileSync } from "node:fs";

import {
  batchClose,
  batchCreateEnvs,
  batchReset,
  batchStepPacked,
  clean,
  connect,
  createRobotEnv,
  gymClose,
  gymObserve,
  gymRender,
  gymReset,
  gymStep,
  type PackedBatchStep,
} from "../src/index.js";

const models = new URL("../../../../models/", import.meta.url);
const pendulum = JSON.parse(readFileSync(new URL("pendulum.json", models), "utf8"));
const arm2 = JSON.parse(readFileSync(new URL("arm2.json", models), "utf8"));

const client = connect({ address: process.argv[2] });

// Errors are printed for people: the message (an unreachable server is named, with what to
// do), not the stack.
try {
  const server = await client.simulator.getServerInfo({});
  console.log(`server ${server.version} with ${server.threads} threads`);

  // One environment: the seed's pendulum, which starts upright and falls. The pose of an
  // end effector is its centre of mass: the arm's middle, not its tip.
  const env = await createRobotEnv({ document: pendulum, end_effector_ids: ["arm"] }, client);
  console.log(
    `${env.env_id}: ${env.num_joints} joint(s), action_dim ${env.action_dim}, observation_dim ${env.observation_dim}`,
  );
  const first = await gymReset(env, client);
  console.log(`reset: pose ${JSON.stringify(first.end_effector_poses[0])}`);
  // The seed pendulum's arm weighs 0.64 g: 1e-4 N·m for one step (1/240 s) is a push.
  const pushed = await gymStep({ ...env, action_type: "torque", values: [1e-4] }, client);
  console.log(`pushed: ${pushed.observation.joint_positions[0]!.toFixed(3)} deg`);
  for (let i = 0; i < 59; i++) {
    await gymStep({ ...env, action_type: "torque", values: [0] }, client); // free swing
  }
  const now = await gymObserve(env, client);
  const [angle, speed] = [now.joint_positions[0]!, now.joint_velocities[0]!];
  console.log(`after 0.25 s: ${angle.toFixed(2)} deg at ${speed.toFixed(2)} deg/s`);
  // A picture of it, from the front: a PNG, written under dist/ (the build folder, which git
  // ignores) rather than into the repository.
  const picture = await gymRender({ ...env, camera: "front" }, client);
  mkdirSync("dist", { recursive: true });
  writeFileSync("dist/pendulum.png", picture.png);
  console.log(`dist/pendulum.png: ${picture.description}`);
  await gymClose(env, client);

  // A batch of 16 two-joint arms, stepped with one packed Float32Array of
  // n_envs × action_dim values, row-major.
  const batch = await batchCreateEnvs(
    { document: arm2, n_envs: 16, end_effector_ids: ["forearm"], seed: 7 },
    client,
  );
  await batchReset({ ...batch, seed: 7 }, client);
  // Position targets in degrees: shoulder +20, elbow -30 (its limits are -120..0).
  const targets = new Float32Array(batch.n_envs * batch.action_dim).map((_, i) => (i % 2 === 0 ? 20 : -30));
  let step: PackedBatchStep | undefined;
  for (let t = 0; t < 240; t++) {
    step = await batchStepPacked({ ...batch, action_type: "position", actions: targets }, client); // deg
  }
  const env0 = Array.from(step!.observations.subarray(0, batch.action_dim), clean);
  console.log(`env 0 after 1 s of position control: ${JSON.stringify(env0)}`);
  await batchClose(batch, client);
} catch (err) {
  console.error(`error: ${err instanceof Error ? err.message : String(err)}`);
  process.exitCode = 1;
} finally {
  client.close();
}
