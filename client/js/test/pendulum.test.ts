/**
 * The user guide's pendulum, through the guide's functions:
 * - its session ("Walking Through a Pendulum Swing": create with the guide's arguments,
 *   reset, a push of 2 N·m, free steps, observe) gives the Rust client's numbers bit for
 *   bit, in the MCP tools' JSON. The expected values (test/pendulum_expected.ts) are the
 *   MCP adapter's replies (the Rust client `gymfleet-client` behind the guide's tools) for
 *   the same calls, recorded by scripts/pendulum-expected.mjs; the Python package (the
 *   same Rust client, through PyO3) gave the same 32-bit floats for all 103 steps when
 *   they were recorded;
 * - the Rust end-to-end walkthrough's checks (tests/tests/e2e/walkthrough.rs) hold;
 * - the first session (examples/first_session.ts, which client/js/README.md shows) prints
 *   what the Rust example `first_session` prints (README.md, "Its output on a fresh
 *   server"), line for line.
 */

import assert from "node:assert/strict";
import { execFile } from "node:child_process";
import { readFileSync } from "node:fs";
import { after, before, test } from "node:test";
import { fileURLToPath } from "node:url";
import { promisify } from "node:util";

import {
  Code,
  connect,
  createRobotEnv,
  gymClose,
  gymObserve,
  gymReset,
  gymStep,
  NotFound,
  type GymfleetClient,
} from "../src/index.js";
import * as expected from "./pendulum_expected.js";
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

/** `actual` is the MCP tool's reply `text`: the same values (32-bit floats compared
 * through their shortest decimal forms, so bit for bit; -0 is not 0) with the same keys in
 * the same order. */
function sameAsMcp(actual: unknown, text: string, what: string): void {
  const mcp: unknown = JSON.parse(text);
  assert.deepStrictEqual(actual, mcp, what);
  assert.equal(JSON.stringify(actual), JSON.stringify(mcp), `${what}: key order`);
}

test("the guide's pendulum session gives the Rust client's numbers, bit for bit", async () => {
  const created = await createRobotEnv(
    { document: model("pendulum"), end_effector_ids: ["arm"], dt: 0.004166, substeps: 4, max_steps: 1000 },
    client,
  );
  assert.match(created.env_id, /^sim_\d+$/);
  // The adapter numbers its own envs; the rest is the server's answer.
  sameAsMcp({ ...created, env_id: "sim_1" }, expected.created, "create_robot_env");
  const env = { env_id: created.env_id };

  sameAsMcp(await gymReset(env, client), expected.reset, "gym_reset");
  assert.equal(expected.steps.length, 103);
  for (const [i, text] of expected.steps.entries()) {
    const values = [i === 0 ? 2.0 : 0.0];
    sameAsMcp(await gymStep({ ...env, action_type: "torque", values }, client), text, `gym_step ${i + 1}`);
  }
  sameAsMcp(await gymObserve(env, client), expected.observed, "gym_observe");
  assert.deepEqual(await gymClose(env, client), { env_id: created.env_id, closed: true });
});

test("the Rust end-to-end walkthrough's checks hold", async () => {
  const created = await createRobotEnv({ document: model("pendulum"), end_effector_ids: ["arm"] }, client);
  assert.deepEqual([created.num_joints, created.action_dim, created.observation_dim], [1, 1, 9]);
  assert.match(created.env_id, /^sim_\d+$/);
  assert.deepEqual(created.end_effector_ids, ["arm"]);
  assert.deepEqual([created.substeps, created.max_steps], [5, 1000]);
  assert.ok(Math.abs(created.dt - 1 / 240) < 1e-12);
  assert.equal(created.joints.length, 1);
  const [joint] = created.joints;
  assert.deepEqual(
    [joint!.type, joint!.parent, joint!.child, joint!.limits[0]!.unit],
    ["revolute", "base", "arm", "deg"],
  );

  const env = { env_id: created.env_id };
  const first = await gymReset(env, client);
  const close = (got: number[], want: number[]) =>
    assert.ok(
      got.length === want.length && got.every((x, i) => Math.abs(x - want[i]!) <= 1e-4),
      `${got} vs ${want}`,
    );
  close(first.joint_positions, [0]);
  close(first.joint_velocities, [0]);
  assert.equal(first.end_effector_poses.length, 1);
  close(first.end_effector_poses[0]!, [10, 10, 25, 1, 0, 0, 0]);

  const pushed = await gymStep({ ...env, action_type: "torque", values: [2.0] }, client);
  assert.ok(pushed.observation.joint_positions[0]! > 0, "positive torque increases the angle");
  assert.ok(pushed.observation.joint_velocities[0]! > 0);
  assert.deepEqual(
    [pushed.reward, pushed.done, pushed.terminated, pushed.truncated],
    [0, false, false, false],
  );

  // Free swing: the upright pendulum keeps falling the way it was pushed.
  let last = pushed;
  for (let step = 2; step <= 60; step++) {
    const next = await gymStep({ ...env, action_type: "torque", values: [0.0] }, client);
    assert.ok(
      next.observation.joint_positions[0]! > last.observation.joint_positions[0]!,
      "it keeps falling",
    );
    last = next;
  }
  assert.deepStrictEqual(await gymObserve(env, client), last.observation, "observe does not step");

  await gymClose(env, client);
  const calls = [
    () => gymStep({ ...env, action_type: "torque", values: [0.0] }, client),
    () => gymObserve(env, client),
    () => gymReset(env, client),
    () => gymClose(env, client),
  ];
  for (const call of calls) {
    await assert.rejects(call, (err: unknown) => {
      assert.ok(err instanceof NotFound, String(err));
      assert.equal(err.code, Code.NotFound);
      assert.ok(err.message.includes(`"${created.env_id}"`), err.message);
      return true;
    });
  }
});

test("the first session example prints what the Rust example prints in README.md", async () => {
  // README.md, "A first session": the output of client/examples/first_session.rs on a fresh
  // server with 2 threads. Lists are compared as numbers (Rust prints 10.0, JSON 10).
  const readme = readFileSync(new URL("../../../../README.md", import.meta.url), "utf8");
  const block = /Its output on a fresh server:\n\n(?:<!--[^\n]*-->\n)?```text\n([^]*?)```/.exec(readme);
  assert.ok(block, "README.md has the Rust example's output");
  const lines = (text: string) =>
    text
      .trim()
      .split("\n")
      .map((line) => line.replace(/\[[-\d., ]*\]/g, (list) => JSON.stringify(JSON.parse(list))));
  const rust = lines(block[1]!.replace("target/pendulum.png", "dist/pendulum.png"));

  const fresh = await startServer();
  try {
    const example = fileURLToPath(new URL("../examples/first_session.js", import.meta.url));
    const cwd = fileURLToPath(new URL("../../", import.meta.url));
    const { stdout } = await promisify(execFile)(process.execPath, [example, fresh.address], { cwd });
    assert.deepEqual(lines(stdout), rust);
  } finally {
    await fresh.stop();
  }
});

test("the first session example prints an unreachable server's error for people, exit status 1", async () => {
  const closed = await startServer();
  await closed.stop();
  const example = fileURLToPath(new URL("../examples/first_session.js", import.meta.url));
  const cwd = fileURLToPath(new URL("../../", import.meta.url));
  const run = promisify(execFile)(process.execPath, [example, closed.address], { cwd });
  await assert.rejects(run, (err: { code?: number; stderr?: string }) => {
    assert.equal(err.code, 1);
    assert.equal(
      err.stderr,
      `error: cannot connect to the gymfleet server at ${closed.address}: connect ECONNREFUSED ${closed.address}. ` +
        "Is the server running? To use another one, pass its address as `address` to connect (or set GYMFLEET_SERVER).\n",
    );
    return true;
  });
});
