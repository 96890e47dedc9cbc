/**
 * Every error class and message: the status-code mapping (the Rust client's), each status
 * a server here can be made to answer, and every argument this client refuses itself,
 * with its message.
 */

import assert from "node:assert/strict";
import { after, before, test } from "node:test";

import { ConnectError } from "@connectrpc/connect";

import {
  batchClose,
  batchCreateEnvs,
  batchStep,
  batchStepPacked,
  Code,
  connect,
  createRobotEnv,
  DeadlineExceeded,
  FailedPrecondition,
  gymLoadState,
  gymRender,
  gymReset,
  gymStep,
  GymfleetError,
  Internal,
  InvalidArgument,
  NotFound,
  ResourceExhausted,
  toGymfleetError,
  Unauthenticated,
  Unavailable,
  type GymfleetClient,
} from "../src/index.js";
import { model, startServer, type TestServer } from "./server.js";

let server: TestServer;
let client: GymfleetClient;

before(async () => {
  server = await startServer(["--max-batch-size", "8"]);
  client = connect({ address: server.address });
});

after(async () => {
  client.close();
  await server.stop();
});

/** Asserts that `call` fails with `Class`, `code` and exactly `message`. */
async function fails(call: () => unknown, Class: typeof GymfleetError, code: Code, message: string | RegExp) {
  await assert.rejects(
    async () => call(),
    (err: unknown) => {
      assert.ok(err instanceof Class, `${String(err)} is not ${Class.name}`);
      assert.ok(err instanceof GymfleetError && err instanceof Error);
      assert.equal(err.name, Class.name);
      assert.equal(err.code, code);
      if (typeof message === "string") assert.equal(err.message, message);
      else assert.match(err.message, message);
      return true;
    },
  );
}

const invalid = (call: () => unknown, message: string | RegExp) =>
  fails(call, InvalidArgument, Code.InvalidArgument, message);

test("each gRPC status code maps to its class, keeping the code and the server's message", () => {
  const cases: [Code, typeof GymfleetError][] = [
    [Code.InvalidArgument, InvalidArgument],
    [Code.NotFound, NotFound],
    [Code.ResourceExhausted, ResourceExhausted],
    [Code.OutOfRange, ResourceExhausted],
    [Code.FailedPrecondition, FailedPrecondition],
    [Code.Unauthenticated, Unauthenticated],
    [Code.DeadlineExceeded, DeadlineExceeded],
    [Code.Unavailable, Unavailable],
    [Code.Canceled, Unavailable],
    [Code.Aborted, Unavailable],
    [Code.Internal, Internal],
    [Code.Unknown, Internal],
    [Code.DataLoss, Internal],
    [Code.AlreadyExists, Internal],
    [Code.PermissionDenied, Internal],
    [Code.Unimplemented, Internal],
  ];
  for (const [code, Class] of cases) {
    const wire = new ConnectError("sim_7: the server's words", code);
    const err = toGymfleetError(wire);
    assert.ok(err instanceof Class, `${Code[code]} -> ${err.name}`);
    assert.deepEqual([err.code, err.message, err.cause], [code, "sim_7: the server's words", wire]);
  }
  const again = toGymfleetError(new NotFound("gone", Code.NotFound));
  assert.equal(again.message, "gone");
  const odd = toGymfleetError(new Error("boom"));
  assert.deepEqual([odd.name, odd.code, odd.message], ["Internal", Code.Unknown, "boom"]);
});

test("server errors: INVALID_ARGUMENT with the JSON path, NOT_FOUND, RESOURCE_EXHAUSTED, FAILED_PRECONDITION", async () => {
  const bad = { parts: [], assembly: { instances: [{ part: "X", name: "x" }] } };
  await invalid(
    () => createRobotEnv({ document: bad }, client),
    'assembly.instances[0].part: unknown part "X" (known: none)',
  );
  await invalid(() => createRobotEnv({ document: "{ not json" }, client), /^document: /);
  const env = await createRobotEnv({ document: model("pendulum") }, client);
  await invalid(
    () => gymStep({ ...env, action_type: "torque", values: [1, 2] }, client),
    "values: expected 1 action value (one per actuated DOF), got 2",
  );
  await fails(
    () => gymReset({ env_id: "sim_999" }, client),
    NotFound,
    Code.NotFound,
    'environment "sim_999" not found: it was closed, reclaimed after idling, or never existed',
  );
  await fails(
    () => batchCreateEnvs({ document: model("pendulum"), n_envs: 9 }, client),
    ResourceExhausted,
    Code.ResourceExhausted,
    "n_envs: 9 exceeds the server's max batch size of 8; split the batch, or raise the limit with --max-batch-size (GYMFLEET_MAX_BATCH_SIZE)",
  );
  await fails(
    () => client.simulator.getRandomization({ envId: env.env_id }),
    FailedPrecondition,
    Code.FailedPrecondition,
    `"${env.env_id}" was created without randomize: it draws no factors`,
  );
});

/** Asserts that `call` fails with the server's `reason` (and a limit's `limit`). */
async function because(call: () => unknown, reason: string, limit?: string) {
  await assert.rejects(
    async () => call(),
    (err: unknown) => {
      assert.ok(err instanceof GymfleetError, String(err));
      assert.deepEqual([err.reason, err.limit], [reason, limit], err.message);
      return true;
    },
  );
}

test("every server error carries its reason: the status's gymfleet-reason metadata", async () => {
  const bad = { parts: [], assembly: { instances: [{ part: "X", name: "x" }] } };
  await because(() => createRobotEnv({ document: bad }, client), "INVALID_DOCUMENT");
  await because(() => createRobotEnv({ model: "no_such_model" }, client), "MODEL_NOT_FOUND");
  await because(
    () => createRobotEnv({ document: model("pendulum"), end_effector_ids: ["nowhere"] }, client),
    "UNKNOWN_NAME",
  );
  const env = await createRobotEnv({ document: model("pendulum") }, client);
  await because(() => gymStep({ ...env, action_type: "torque", values: [1, 2] }, client), "INVALID_ACTION");
  await because(() => gymReset({ env_id: "sim_999" }, client), "ENV_NOT_FOUND");
  await because(() => batchClose({ batch_id: "batch_999" }, client), "BATCH_NOT_FOUND");
  await because(() => client.simulator.getRandomization({ envId: env.env_id }), "NOT_RANDOMIZED");
  await because(
    () => client.simulator.loadState({ envId: env.env_id, state: new Uint8Array([1, 2, 3]) }),
    "INVALID_STATE",
  );
  await because(
    () => batchCreateEnvs({ document: model("pendulum"), n_envs: 9 }, client),
    "LIMIT_EXCEEDED",
    "--max-batch-size",
  );
  // A diverged env must be reset first.
  await gymReset(env, client);
  const diverged = await gymStep({ ...env, action_type: "torque", values: [1e12] }, client);
  assert.ok(diverged.terminated);
  await because(() => gymStep({ ...env, action_type: "torque", values: [0] }, client), "NEEDS_RESET");
  // This client's own action checks stand in for the server's.
  await because(() => gymStep({ ...env, action_type: "torque", values: [NaN] }, client), "INVALID_ACTION");
  // What the client found itself has none.
  const wire = toGymfleetError(new ConnectError("no reason sent", Code.Internal));
  assert.equal(wire.reason, undefined);
});

test("transport errors: an unreachable server is UNAVAILABLE, a late reply DEADLINE_EXCEEDED", async () => {
  const closed = await startServer();
  await closed.stop();
  const gone = connect({ address: closed.address });
  await fails(
    () => gone.simulator.getServerInfo({}),
    Unavailable,
    Code.Unavailable,
    `cannot connect to the gymfleet server at ${closed.address}: connect ECONNREFUSED ${closed.address}. Is the server running? To use another one, pass its address as \`address\` to connect (or set GYMFLEET_SERVER).`,
  );
  // 8 chains of 20 links, 500 substeps each: far more than a millisecond.
  const slow = connect({ address: server.address, timeoutMs: 1 });
  const batch = await batchCreateEnvs({ document: model("chain20"), n_envs: 8, substeps: 500 }, client);
  const actions = new Float32Array(8 * batch.action_dim);
  await fails(
    () => batchStepPacked({ ...batch, action_type: "torque", actions }, slow),
    DeadlineExceeded,
    Code.DeadlineExceeded,
    "the operation timed out",
  );
  slow.close();
  await batchClose(batch, client);
});

test("arguments refused before any call, with what was expected and what was given", async () => {
  const env = await createRobotEnv({ document: model("pendulum") }, client);
  const step = (values: unknown[], action_type = "torque") =>
    gymStep({ ...env, action_type: action_type as "torque", values: values as number[] }, client);
  const finite = "; every action value must be a finite number";
  await invalid(
    () => step([0], "force"),
    'action_type: expected "torque", "position" or "velocity", got "force"',
  );
  await invalid(() => step([null]), `values[0] is null${finite}`);
  await invalid(() => step([undefined]), `values[0] is undefined${finite}`);
  await invalid(() => step(["0.5"]), `values[0] is the string "0.5", not a number${finite}`);
  await invalid(() => step([true]), `values[0] is a boolean, not a number${finite}`);
  await invalid(() => step([[1]]), `values[0] is an array, not a number${finite}`);
  await invalid(() => step([{}]), `values[0] is an object, not a number${finite}`);
  await invalid(() => step([NaN]), `values[0] is NaN${finite}`);
  await invalid(() => step([Infinity]), `values[0] is infinite (inf)${finite}`);
  await invalid(() => step([-Infinity]), `values[0] is infinite (-inf)${finite}`);
  await invalid(
    () => step([1e39]),
    `values[0] = 1e+39 is out of range (actions are 32-bit floats, at most about 3.4e38)${finite}`,
  );

  for (const seed of [-1, 1.5, 2n ** 64n]) {
    await invalid(
      () => gymReset({ ...env, seed }, client),
      `seed: expected a non-negative safe integer, or a bigint below 2^64; got ${seed}`,
    );
  }
  await invalid(
    () => gymRender({ ...env, camera: "diagonal" as "iso" }, client),
    'camera: expected "iso", "front", "side" or "top", got "diagonal"',
  );
  await invalid(
    () => gymLoadState({ ...env, state: "not base64!" }, client),
    "state: not the base64 text gymSaveState returns",
  );

  const pendulum = model("pendulum");
  await invalid(
    () => createRobotEnv({ document: pendulum, model: "arm2" }, client),
    "give document or model, not both",
  );
  await invalid(
    () => createRobotEnv({}, client),
    "document is required: the assembly document (JSON, MJCF or URDF), or give model: a name from listModels",
  );
  for (const [document, kind] of [
    [[1, 2], "an array"],
    [null, "null"],
    [7, "a number"],
  ] as const) {
    await invalid(
      () => createRobotEnv({ document: document as unknown as string }, client),
      `document must be the assembly document as a JSON object (with "parts" and "assembly"), or a string containing that JSON; got ${kind}`,
    );
  }
  await invalid(
    () => createRobotEnv({ document: pendulum, assets_base64: "@@@@" }, client),
    "assets_base64: not base64",
  );
  const two = { track: { targets: [0] }, upright: { instance: "arm", max_tilt_deg: 10 } };
  for (const task of [two, {}]) {
    await invalid(
      () => createRobotEnv({ document: pendulum, task }, client),
      'task: give exactly one of "reach", "track", "upright" or "terms"',
    );
  }
  await invalid(
    () => batchCreateEnvs({ document: pendulum, n_envs: 2, autoreset: "always" as "disabled" }, client),
    'autoreset: expected "disabled", "same_step" or "next_step", got "always"',
  );
});

test("batch actions: one array of action_dim values per env, checked before the call", async () => {
  const batch = await batchCreateEnvs({ document: model("arm2"), n_envs: 8 }, client);
  const id = batch.batch_id;
  const rows = (n: number) => Array.from({ length: n }, () => [0, 0]);
  const step = (actions: unknown[][]) =>
    batchStep({ batch_id: id, action_type: "torque", actions: actions as number[][] }, client);
  await invalid(
    () => step(rows(3)),
    `${id} expects 8 arrays of 2 values (one array per env, action_dim values each); got 3 arrays`,
  );
  const ragged = rows(8);
  ragged[4] = [0, 0, 0];
  await invalid(() => step(ragged), `${id} expects 8 arrays of 2 values; array 4 has 3`);
  const inf = rows(8);
  inf[1] = [Infinity, 0];
  await invalid(
    () => step(inf),
    "actions[1][0] is infinite (inf); every action value must be a finite number",
  );
  const packed = new Float32Array(16);
  packed[3] = NaN;
  await invalid(
    () => batchStepPacked({ batch_id: id, action_type: "torque", actions: packed }, client),
    "actions[3] is NaN; every action value must be a finite number",
  );
  await invalid(
    () => batchStepPacked({ batch_id: id, action_type: "torque", actions: new Float32Array(3) }, client),
    /^actions: expected 16 values \(8 envs × 2 DOF\), got 3$/,
  );
  // A batch this client did not create: the grouped functions need its layout.
  await fails(
    () => batchStep({ batch_id: "batch_77", action_type: "torque", actions: [] }, client),
    NotFound,
    Code.NotFound,
    `unknown batch_id "batch_77": this client has no open batch with this id (open: ${id}). ` +
      "Create one with batchCreateEnvs; batchStepPacked and batchResetPacked take any batch of the server.",
  );
});

test("connection settings are checked when connecting", async () => {
  for (const address of ["localhost", "a:1,b:2", "ftp://h:1"]) {
    await invalid(
      () => connect({ address }),
      `address ${JSON.stringify(address)}: expected host:port, http://host:port or https://host:port`,
    );
  }
  for (const token of ["", "has space"]) {
    await invalid(
      () => connect({ token }),
      "token: expected a non-empty bearer token of printable ASCII without spaces",
    );
  }
  await invalid(
    () => connect({ tls: { certFile: "client.pem" } }),
    "tls: a client certificate and its key go together: give both or neither",
  );
  await invalid(
    () => connect({ tls: { caFile: "/nonexistent/ca.pem" } }),
    "TLS CA file /nonexistent/ca.pem: ENOENT: no such file or directory, open '/nonexistent/ca.pem'",
  );
  process.env.GYMFLEET_TLS_CLIENT_KEY = "client.key";
  try {
    await invalid(
      () => connect(),
      "GYMFLEET_TLS_CLIENT_CERT and GYMFLEET_TLS_CLIENT_KEY go together: set both or neither",
    );
  } finally {
    delete process.env.GYMFLEET_TLS_CLIENT_KEY;
  }
});
