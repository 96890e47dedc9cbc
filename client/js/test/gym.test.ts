/**
 * The guide's single-env functions beyond the pendulum: the default connection from
 * GYMFLEET_SERVER, the 2-DOF arm, tasks and randomisation, render, saved states and the
 * model library; and the typed client for the rest (server info, randomisation draws).
 */

import assert from "node:assert/strict";
import { fileURLToPath } from "node:url";
import { after, before, test } from "node:test";

import {
  clean,
  connect,
  createRobotEnv,
  gymClose,
  gymLoadState,
  gymObserve,
  gymRender,
  gymReset,
  gymSaveState,
  gymSetMocapPose,
  gymStep,
  listModels,
  type GymfleetClient,
} from "../src/index.js";
import { model, startServer, type TestServer } from "./server.js";

let server: TestServer;
let client: GymfleetClient;

before(async () => {
  const models = fileURLToPath(new URL("../../../../models", import.meta.url));
  server = await startServer(["--models", models]);
  client = connect({ address: server.address });
});

after(async () => {
  client.close();
  await server.stop();
});

test("the functions called with no client use GYMFLEET_SERVER", async () => {
  process.env.GYMFLEET_SERVER = server.address;
  const env = await createRobotEnv({ model: "pendulum", end_effector_ids: ["arm"] });
  assert.deepEqual(await gymObserve(env), await gymReset(env));
  const step = await gymStep({ ...env, action_type: "velocity", values: [90] });
  assert.ok(step.observation.joint_velocities[0]! > 0);
  assert.deepEqual(await gymClose(env), { env_id: env.env_id, closed: true });
  assert.deepEqual(await listModels(), await listModels(client));
});

test("the two-joint arm: limits, position control and an exact reset", async () => {
  const env = await createRobotEnv(
    { document: model("arm2"), end_effector_ids: ["forearm"], seed: 3 },
    client,
  );
  assert.deepEqual([env.num_joints, env.action_dim, env.observation_dim], [2, 2, 11]);
  const limits = env.joints.map((j) => [j.limits[0]!.min!, j.limits[0]!.max!]);
  for (const [got, want] of limits.map((l, i) => [
    l,
    [
      [-90, 90],
      [-120, 0],
    ][i]!,
  ])) {
    assert.ok(Math.abs(got![0]! - want![0]!) < 1e-9 && Math.abs(got![1]! - want![1]!) < 1e-9, `${limits}`);
  }
  assert.equal(env.joints[1]!.parent, "upper");
  assert.equal(env.joints[0]!.torque_bounds.length, 1);

  const first = await gymReset({ ...env, seed: 3 }, client);
  for (let i = 0; i < 20; i++) {
    const step = await gymStep({ ...env, action_type: "position", values: [30, -30] }, client);
    assert.equal(step.observation.end_effector_poses[0]!.length, 7);
  }
  const moved = await gymObserve(env, client);
  assert.ok(moved.joint_positions[0]! > 0 && moved.joint_positions[1]! < 0, JSON.stringify(moved));
  assert.deepStrictEqual(await gymReset(env, client), first, "reset is exact");
  await gymClose(env, client);
});

test("a reach task adds its target and computes the reward", async () => {
  const env = await createRobotEnv(
    {
      document: model("arm2"),
      end_effector_ids: ["forearm"],
      task: { reach: { end_effector: "forearm", target: { x: 20, y: 0, z: 40 } }, action_cost: 100 },
    },
    client,
  );
  assert.equal(env.observation_dim, 14);
  const first = await gymReset(env, client);
  assert.deepEqual(first.target, [20, 0, 40]);
  // Reward: minus the distance to the target (mm), minus 100 × Σ a².
  for (const values of [
    [0, 0],
    [0.01, 0],
  ]) {
    const step = await gymStep({ ...env, action_type: "torque", values }, client);
    const [x, y, z] = step.observation.end_effector_poses[0]!;
    const want = -Math.hypot(x! - 20, y!, z! - 40) - 100 * values[0]! ** 2;
    assert.ok(Math.abs(step.reward - want) < 1e-4, `${step.reward} vs ${want}`);
  }
  await gymClose(env, client);
});

test("track, upright and terms tasks: rewards, terminations and named terms", async () => {
  const track = await createRobotEnv(
    { document: model("arm2"), task: { track: { targets: [10, -10], tolerance: 0.5 } } },
    client,
  );
  await gymReset(track, client);
  const tracked = await gymStep({ ...track, action_type: "position", values: [10, -10] }, client);
  const [a, b] = tracked.observation.joint_positions;
  assert.ok(Math.abs(tracked.reward + Math.hypot(a! - 10, b! + 10)) < 1e-3);

  // The seed pendulum starts upright and falls: past 10° the episode ends.
  const upright = await createRobotEnv(
    { document: model("pendulum"), task: { upright: { instance: "arm", max_tilt_deg: 10 } } },
    client,
  );
  await gymReset(upright, client);
  let step = await gymStep({ ...upright, action_type: "torque", values: [1e-4] }, client);
  assert.equal(step.reward, 1);
  while (!step.done) {
    step = await gymStep({ ...upright, action_type: "torque", values: [0] }, client);
  }
  assert.deepEqual([step.terminated, step.termination_reason, step.reward], [true, "fell", 0]);

  const terms = await createRobotEnv(
    {
      document: model("pendulum"),
      task: {
        terms: {
          terms: [
            { name: "speed", weight: 0.5, value: { joint_velocity: "arm" } },
            { name: "ctrl", weight: -1, ctrl_cost: {} },
          ],
        },
      },
    },
    client,
  );
  await gymReset(terms, client);
  const named = await gymStep({ ...terms, action_type: "torque", values: [1e-4] }, client);
  assert.deepEqual(Object.keys(named.terms!), ["ctrl", "speed"]);
  assert.equal(named.terms!.speed, named.observation.joint_velocities[0]);
  assert.equal(named.terms!.ctrl, clean(Math.fround(Math.fround(1e-4) ** 2)));
  for (const env of [track, upright, terms]) await gymClose(env, client);
});

test("randomisation draws are read through the typed client", async () => {
  const env = await createRobotEnv(
    { document: model("pendulum"), seed: 5, randomize: { mass_scale: { min: 0.5, max: 0.6 } } },
    client,
  );
  await gymReset(env, client);
  const draws = await client.simulator.getRandomization({ envId: env.env_id });
  assert.deepEqual(
    draws.instances.map((i) => i.name),
    ["base", "arm"],
  );
  for (const draw of draws.instances) {
    assert.ok(draw.massScale >= 0.5 && draw.massScale <= 0.6, `${draw.massScale}`);
    assert.equal(draw.frictionScale, 1);
  }
  await gymClose(env, client);
});

test("gymRender returns a PNG and what it shows", async () => {
  const env = await createRobotEnv({ model: "pendulum", end_effector_ids: ["arm"] }, client);
  const picture = await gymRender({ ...env, camera: "front" }, client);
  assert.deepEqual([picture.env_id, picture.width, picture.height], [env.env_id, 320, 240]);
  assert.deepEqual([...picture.png.subarray(0, 8)], [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]);
  assert.ok(picture.description.includes("front view"), picture.description);
  assert.ok(picture.grid_mm > 0);
  const sized = await gymRender(
    { ...env, width: 64, eye: [100, -100, 100], target: [10, 10, 20], fov_deg: 30 },
    client,
  );
  assert.deepEqual([sized.width, sized.height], [64, 240]);
  const flat = await gymRender({ ...env, camera: "top", orthographic: true, width: 32, height: 48 }, client);
  assert.deepEqual([flat.width, flat.height], [32, 48]);
  await gymClose(env, client);
});

test("a saved state, loaded back, continues bit for bit", async () => {
  const env = await createRobotEnv({ document: model("arm2"), end_effector_ids: ["forearm"] }, client);
  await gymReset(env, client);
  await gymStep({ ...env, action_type: "torque", values: [1e-4, -1e-4] }, client);
  const saved = await gymSaveState(env, client);
  assert.equal(saved.env_id, env.env_id);
  assert.equal(Buffer.from(saved.state, "base64").length, saved.bytes);
  const here = await gymObserve(env, client);
  const next = await gymStep({ ...env, action_type: "torque", values: [2e-4, 0] }, client);

  // Into a second env of the same document: it continues as the first did.
  const twin = await createRobotEnv(
    { document: model("arm2"), end_effector_ids: ["forearm"], seed: 9 },
    client,
  );
  assert.deepStrictEqual(await gymLoadState({ ...twin, state: saved.state }, client), here);
  assert.deepStrictEqual(await gymStep({ ...twin, action_type: "torque", values: [2e-4, 0] }, client), next);
  for (const e of [env, twin]) await gymClose(e, client);
});

test("listModels lists the server's library, and a model creates an env", async () => {
  const { models } = await listModels(client);
  assert.deepEqual(
    models.map((m) => m.name),
    ["arm2", "arm6", "chain20", "fourbar", "pendulum"],
  );
  assert.deepEqual(
    models.find((m) => m.name === "arm2"),
    { name: "arm2", format: "json", dofs: 2, action_dim: 2 },
  );
  const env = await createRobotEnv({ model: "arm2" }, client);
  assert.equal(env.action_dim, 2);
  await gymClose(env, client);
});

test("the typed client reaches every RPC: server info and a converted document", async () => {
  const info = await client.simulator.getServerInfo({});
  assert.equal(info.threads, 2);
  assert.equal(info.authRequired, false);
  assert.match(info.instanceId, /^[0-9a-f]{32}$/);
  const converted = await client.simulator.convertDocument({
    documentJson: JSON.stringify(model("pendulum")),
  });
  assert.deepEqual(JSON.parse(converted.documentJson), model("pendulum"));
});

test("a mocap paddle lifts a free box: gymSetMocapPose and free_body_poses", async () => {
  const document = {
    parts: [
      { name: "Anchor", primitive: { type: "sphere", radius: 1 } },
      { name: "Paddle", primitive: { type: "cube", size: { x: 40, y: 40, z: 10 } } },
      { name: "Cube", primitive: { type: "cube", size: { x: 20, y: 20, z: 20 } } },
    ],
    assembly: {
      instances: [
        { part: "Anchor", name: "anchor", collision: { group: 0, mask: 0 } },
        { part: "Paddle", name: "paddle", position: { x: -20, y: -20, z: 0 }, mocap: true },
        { part: "Cube", name: "box", position: { x: -10, y: -10, z: 10 } },
      ],
      joints: [],
    },
  };
  const env = await createRobotEnv({ document }, client);
  assert.deepEqual([env.free_bodies, env.mocap_bodies], [["box"], ["paddle"]]);
  let step = await gymStep({ ...env, action_type: "torque", values: [] }, client);
  for (let k = 1; k <= 60; k++) {
    await gymSetMocapPose({ ...env, body: "paddle", position: [0, 0, 5 + (30 * k) / 60] }, client);
    step = await gymStep({ ...env, action_type: "torque", values: [] }, client);
  }
  const z = step.observation.free_body_poses![0]![2]!;
  assert.ok(Math.abs(z - 50) < 0.5, `the box rides on the paddle at ${z} mm`);
  assert.equal(step.observation.free_body_velocities!.length, 1);
  await assert.rejects(
    () => gymSetMocapPose({ ...env, body: "hand", position: [0, 0, 0] }, client),
    /unknown mocap body "hand" \(known: "paddle"\)/,
  );
  await gymClose(env, client);
});

test("an MJCF file's keyframes: listed at creation, named by gymReset", async () => {
  const xml = `<mujoco><worldbody><body name="arm">
    <joint name="hinge" type="hinge" axis="0 1 0"/>
    <geom type="capsule" fromto="0 0 0 0 0 -.3" size=".02"/>
  </body></worldbody>
  <keyframe><key name="raised" qpos="1.5" qvel="0.5"/></keyframe></mujoco>`;
  const env = await createRobotEnv({ document: xml }, client);
  assert.deepEqual(env.keyframes, ["raised"]);
  const raised = await gymReset({ ...env, keyframe: "raised" }, client);
  // Degrees: MuJoCo's radians as observed in the document's units.
  assert.ok(Math.abs(raised.joint_positions[0]! - (1.5 * 180) / Math.PI) < 1e-3);
  assert.ok(Math.abs(raised.joint_velocities[0]! - (0.5 * 180) / Math.PI) < 1e-3);
  const plain = await gymReset(env, client);
  assert.ok(Math.abs(plain.joint_positions[0]!) < 1e-6);
  await assert.rejects(gymReset({ ...env, keyframe: "home" }, client), (err: Error) =>
    err.message.includes('keyframe: no keyframe is named "home"; the document\'s are "raised"'),
  );
  await gymClose(env, client);
});
