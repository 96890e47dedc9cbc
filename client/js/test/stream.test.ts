/**
 * `batchStream`: EnvPool's asynchronous way over one StreamBatch stream. Sends pipelined
 * (several on the wire) step each listed env as a whole-batch step does, bit for bit; a
 * refused step throws at its `recv` with its env indices, and the sends behind it, which
 * the server did not step, go out again on a new stream and step once.
 */

import assert from "node:assert/strict";
import { after, before, test } from "node:test";

import {
  batchCreateEnvs,
  batchObservePacked,
  batchResetPacked,
  batchStepPacked,
  batchStream,
  connect,
  InvalidArgument,
  type GymfleetClient,
  type StepError,
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

const OPTIONS = {
  document: model("arm2"),
  n_envs: 4,
  end_effector_ids: ["forearm"],
  seed: 2,
  reset_noise: 5,
};
const DIM = 11;
const ACTIONS = [1e-4, 0, 0, 1e-4, -1e-4, 2e-4, 2e-4, -1e-4];

function row(values: Float32Array, k: number): number[] {
  return [...values.subarray(k * DIM, (k + 1) * DIM)];
}

async function reference(): Promise<{ start: Float32Array; stepped: Float32Array }> {
  const whole = await batchCreateEnvs(OPTIONS, client);
  const start = (await batchResetPacked({ batch_id: whole.batch_id, seed: 2 }, client)).observations;
  const stepped = (
    await batchStepPacked({ batch_id: whole.batch_id, action_type: "torque", actions: ACTIONS }, client)
  ).observations;
  return { start, stepped };
}

test("pipelined sends step each env as a whole step does", async () => {
  const want = await reference();
  const batch = await batchCreateEnvs(OPTIONS, client);
  await batchResetPacked({ batch_id: batch.batch_id, seed: 2 }, client);
  const stream = batchStream(batch, client);
  stream.send({
    action_type: "torque",
    actions: [...ACTIONS.slice(2, 4), ...ACTIONS.slice(6, 8)],
    env_indices: [1, 3],
  });
  stream.send({ action_type: "torque", actions: ACTIONS.slice(0, 2), env_indices: [0] });
  stream.send({ action_type: "torque", actions: ACTIONS.slice(4, 6), env_indices: [2] });
  assert.equal(stream.inFlight, 3);
  const got = [await stream.recv(), await stream.recv(), await stream.recv()];
  assert.deepEqual(
    got.map((s) => s.env_indices),
    [[1, 3], [0], [2]],
  );
  assert.deepEqual(row(got[0]!.observations, 0), row(want.stepped, 1));
  assert.deepEqual(row(got[0]!.observations, 1), row(want.stepped, 3));
  assert.deepEqual(row(got[1]!.observations, 0), row(want.stepped, 0));
  assert.deepEqual(row(got[2]!.observations, 0), row(want.stepped, 2));
  await assert.rejects(
    stream.recv(),
    (err: unknown) => err instanceof InvalidArgument && /no step was sent/.test(String(err)),
  );
  stream.close();
});

test("a refused send throws at its recv; the sends behind it step once, on a new stream", async () => {
  const want = await reference();
  const batch = await batchCreateEnvs(OPTIONS, client);
  await batchResetPacked({ batch_id: batch.batch_id, seed: 2 }, client);
  const stream = batchStream(batch, client);
  stream.send({ action_type: "torque", actions: ACTIONS.slice(0, 2), env_indices: [0] });
  stream.send({ action_type: "torque", actions: [0, 0, 0, 0], env_indices: [1] }); // 4 values for 1 env
  stream.send({ action_type: "torque", actions: ACTIONS.slice(4, 6), env_indices: [2] });
  assert.deepEqual(row((await stream.recv()).observations, 0), row(want.stepped, 0));
  await assert.rejects(
    stream.recv(),
    (err: unknown) =>
      err instanceof InvalidArgument &&
      /actions: expected 2 values \(1 env × 2 DOF\), got 4/.test(String(err)) &&
      (err as StepError).envIndices.join() === "1",
  );
  const behind = await stream.recv();
  assert.deepEqual(behind.env_indices, [2]);
  assert.deepEqual(row(behind.observations, 0), row(want.stepped, 2), "env 2 stepped once");
  const now = (await batchObservePacked(batch, client)).observations;
  assert.deepEqual(row(now, 1), row(want.start, 1), "env 1 did not move");
  assert.deepEqual(row(now, 3), row(want.start, 3), "env 3 did not move");
  stream.close();
});
