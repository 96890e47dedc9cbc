/**
 * The guide's batch functions (results grouped by env, as the MCP tools return them), the
 * packed calls (`Float32Array` rows, the wire's values bit for bit), autoreset, and the
 * typed client's StreamBatch.
 */

import assert from "node:assert/strict";
import { after, before, test } from "node:test";

import {
  ActionType,
  batchClose,
  batchCreateEnvs,
  batchObservePacked,
  batchReset,
  batchResetPacked,
  batchStep,
  batchStepPacked,
  clean,
  connect,
  createRobotEnv,
  gymReset,
  gymStep,
  InvalidArgument,
  type GymfleetClient,
  type ObservationJson,
} from "../src/index.js";
import { model, startServer, type TestServer } from "./server.js";

let server: TestServer;
let client: GymfleetClient;

before(async () => {
  server = await startServer();
  client = connect({ address: server.address });
});

after(async () => {
  client.close();
  await server.stop();
});

/** A packed row's floats in the guide's order: positions, velocities, poses, target. */
function flat(o: ObservationJson): number[] {
  return [...o.joint_positions, ...o.joint_velocities, ...o.end_effector_poses.flat(), ...(o.target ?? [])];
}

test("the guide's batch of 16 arms: created, reset and stepped, grouped by env", async () => {
  const batch = await batchCreateEnvs(
    { document: model("arm2"), n_envs: 16, end_effector_ids: ["forearm"] },
    client,
  );
  // The guide's reply, and the MCP tool's fields after it.
  assert.match(batch.batch_id, /^batch_\d+$/);
  assert.deepEqual(Object.keys(batch).slice(0, 5), [
    "batch_id",
    "n_envs",
    "action_dim",
    "observation_dim",
    "num_joints",
  ]);
  assert.deepEqual([batch.n_envs, batch.action_dim, batch.observation_dim, batch.num_joints], [16, 2, 11, 2]);
  assert.deepEqual([batch.autoreset, batch.substeps, batch.joints.length], ["disabled", 5, 2]);

  const reset = await batchReset({ batch_id: batch.batch_id, seed: 7 }, client);
  assert.equal(reset.observations.length, 16);
  assert.deepEqual(reset.observations[0]!.joint_positions, [0, 0]);

  // The guide's actions: one array per env, torques in N·m.
  const actions = Array.from({ length: 16 }, (_, i) => [0.5e-4 * (i % 4), -0.3e-4]);
  const step = await batchStep({ batch_id: batch.batch_id, action_type: "torque", actions }, client);
  assert.equal(step.batch_id, batch.batch_id);
  assert.deepEqual(
    step.results.map((r) => r.env_index),
    [...Array(16).keys()],
  );
  const first = step.results[0]!;
  assert.deepEqual(Object.keys(first), [
    "env_index",
    "observation",
    "reward",
    "done",
    "terminated",
    "truncated",
  ]);
  assert.deepEqual(Object.keys(first.observation), [
    "joint_positions",
    "joint_velocities",
    "end_effector_poses",
  ]);
  assert.equal(first.observation.end_effector_poses[0]!.length, 7);
  assert.ok(step.results[1]!.observation.joint_velocities[0]! > first.observation.joint_velocities[0]!);

  // The same actions on one env give env 3's numbers.
  const single = await createRobotEnv(
    { document: model("arm2"), end_effector_ids: ["forearm"], seed: 10 },
    client,
  );
  await gymReset(single, client);
  const alone = await gymStep({ ...single, action_type: "torque", values: actions[3]! }, client);
  assert.deepStrictEqual(step.results[3]!.observation, alone.observation);
  assert.deepEqual(await batchClose(batch, client), { batch_id: batch.batch_id, closed: true });
});

test("packed calls return the wire's floats as Float32Array rows", async () => {
  const options = { document: model("arm2"), n_envs: 3, end_effector_ids: ["forearm"], seed: 1 };
  const grouped = await batchCreateEnvs(options, client);
  const packed = await batchCreateEnvs(options, client);
  const actions = [
    [1e-4, 0],
    [0, 1e-4],
    [-1e-4, 2e-4],
  ];
  const first = await batchResetPacked({ batch_id: packed.batch_id, seed: 1 }, client);
  const groupedReset = await batchReset({ batch_id: grouped.batch_id, seed: 1 }, client);
  assert.ok(first.observations instanceof Float32Array);
  assert.deepEqual([first.n_envs, first.observation_dim, first.observations.length], [3, 11, 33]);
  assert.deepEqual(
    [...first.observations],
    groupedReset.observations.flatMap((o) => flat(o).map(Math.fround)),
  );

  for (let t = 0; t < 5; t++) {
    const byEnv = await batchStep({ batch_id: grouped.batch_id, action_type: "torque", actions }, client);
    const rows = await batchStepPacked(
      { batch_id: packed.batch_id, action_type: "torque", actions: new Float32Array(actions.flat()) },
      client,
    );
    assert.equal(rows.step_index, t + 1);
    assert.ok(rows.rewards instanceof Float32Array && rows.rewards.length === 3);
    assert.deepEqual(
      [rows.terminated, rows.truncated],
      [
        [false, false, false],
        [false, false, false],
      ],
    );
    for (const [env, result] of byEnv.results.entries()) {
      const row = rows.observations.subarray(env * 11, (env + 1) * 11);
      // Each packed float is the 32-bit float whose shortest form the grouped reply gives.
      assert.deepEqual([...row].map(clean), flat(result.observation));
      assert.deepEqual([...row], flat(result.observation).map(Math.fround));
    }
  }
  const observed = await batchObservePacked(packed, client);
  assert.deepEqual([observed.n_envs, observed.observation_dim], [3, 11]);
  assert.equal(observed.observations.length, 33);

  // Resetting some envs only: the others keep their state.
  const before = observed.observations;
  const partly = await batchResetPacked({ batch_id: packed.batch_id, env_indices: [1] }, client);
  assert.deepEqual([...partly.observations.subarray(0, 11)], [...before.subarray(0, 11)]);
  assert.deepEqual([...partly.observations.subarray(11, 22)], [...first.observations.subarray(11, 22)]);
  for (const b of [grouped, packed]) await batchClose(b, client);
});

test("same-step autoreset returns each ended episode's last observation", async () => {
  const batch = await batchCreateEnvs(
    {
      document: model("pendulum"),
      n_envs: 2,
      end_effector_ids: ["arm"],
      max_steps: 3,
      autoreset: "same_step",
    },
    client,
  );
  assert.equal(batch.autoreset, "same_step");
  const reset = await batchReset(batch, client);
  const actions = [[1e-4], [-1e-4]];
  let step = await batchStep({ ...batch, action_type: "torque", actions }, client);
  step = await batchStep({ ...batch, action_type: "torque", actions }, client);
  assert.equal(step.results[0]!.final_observation, undefined);
  step = await batchStep({ ...batch, action_type: "torque", actions }, client);
  for (const [env, result] of step.results.entries()) {
    assert.deepEqual([result.truncated, result.done, result.terminated], [true, true, false]);
    assert.deepStrictEqual(result.observation, reset.observations[env], "the row is the new episode's first");
    assert.notDeepEqual(result.final_observation!.joint_positions, [0]);
  }
  assert.ok(step.results[0]!.final_observation!.joint_positions[0]! > 0);
  assert.ok(step.results[1]!.final_observation!.joint_positions[0]! < 0);
  await batchClose(batch, client);
});

test("the typed client streams batch steps, in order, and ends on an error", async () => {
  const batch = await batchCreateEnvs(
    { document: model("pendulum"), n_envs: 2, end_effector_ids: ["arm"] },
    client,
  );
  await batchReset(batch, client);
  async function* requests(actions: number[][]) {
    for (const a of actions) yield { batchId: batch.batch_id, actionType: ActionType.TORQUE, actions: a };
  }
  const indices: bigint[] = [];
  for await (const result of client.simulator.streamBatch(
    requests([
      [1e-4, 0],
      [0, 0],
      [0, 0],
    ]),
  )) {
    indices.push(result.stepIndex);
    assert.equal(result.observations.length, 18);
  }
  assert.deepEqual(indices, [1n, 2n, 3n]);
  await assert.rejects(
    async () => {
      for await (const _ of client.simulator.streamBatch(requests([[0, 0], [0]]))) {
        // the first result arrives; the second request is refused
      }
    },
    (err: unknown) => err instanceof InvalidArgument && err.code === 3 && /actions/.test(err.message),
  );
  await batchClose(batch, client);
});

test("a packed step of some envs steps them as a whole step does, and only them", async () => {
  const options = {
    document: model("arm2"),
    n_envs: 4,
    end_effector_ids: ["forearm"],
    seed: 2,
    reset_noise: 5,
  };
  const whole = await batchCreateEnvs(options, client);
  const some = await batchCreateEnvs(options, client);
  await batchResetPacked({ batch_id: whole.batch_id, seed: 2 }, client);
  const start = await batchResetPacked({ batch_id: some.batch_id, seed: 2 }, client);
  const actions = [1e-4, 0, 0, 1e-4, -1e-4, 2e-4, 2e-4, -1e-4];
  const all = await batchStepPacked({ batch_id: whole.batch_id, action_type: "torque", actions }, client);
  assert.deepEqual(all.env_indices, []);
  const part = await batchStepPacked(
    { batch_id: some.batch_id, action_type: "torque", actions: [0, 1e-4, 2e-4, -1e-4], env_indices: [1, 3] },
    client,
  );
  assert.deepEqual([part.n_envs, part.env_indices], [2, [1, 3]]);
  assert.deepEqual([...part.observations.subarray(0, 11)], [...all.observations.subarray(11, 22)]);
  assert.deepEqual([...part.observations.subarray(11, 22)], [...all.observations.subarray(33, 44)]);
  const after = await batchObservePacked(some, client);
  assert.deepEqual(
    [...after.observations.subarray(0, 11)],
    [...start.observations.subarray(0, 11)],
    "env 0 did not move",
  );
  await assert.rejects(
    batchStepPacked(
      { batch_id: some.batch_id, action_type: "torque", actions: [0, 0], env_indices: [3, 1] },
      client,
    ),
    (err: unknown) =>
      err instanceof InvalidArgument &&
      /env_indices\[1\]: expected ascending, distinct indices, got 1 after 3/.test(String(err)),
  );
});
