/**
 * The user guide's batch tools as functions: `batchCreateEnvs`, `batchStep` (one action
 * array per env in, results grouped by env out), `batchReset` and `batchClose`, with the
 * MCP tools' JSON; and the packed calls a training loop wants, `batchStepPacked`,
 * `batchResetPacked` and `batchObservePacked`, whose observations are one row-major
 * `Float32Array` of n_envs × observation_dim floats (the wire's values, bit for bit).
 */

import { type GymfleetClient, defaultClient } from "./client.js";
import { Code, NotFound, invalid } from "./errors.js";
import type { BatchInfo, BatchObservation, BatchStepResult } from "./gen/gymfleet/v1/simulator_pb.js";
import { known } from "./known.js";
import {
  actionType,
  autoreset,
  createFields,
  pushActionValues,
  seed,
  type ActionTypeName,
  type AutoresetName,
  type CreateEnvParams,
} from "./params.js";
import {
  clean,
  batchEnv,
  fromBatchInfo,
  fromRow,
  terms,
  type BatchCreatedJson,
  type ObservationJson,
} from "./shapes.js";

/** The inputs of `batchCreateEnvs`: createRobotEnv's, plus the batch's size. */
export interface CreateBatchParams extends CreateEnvParams {
  /** Number of identical environments (at least 1). Env i is seeded with seed + i. */
  n_envs: number;
  /** What happens to an env whose episode ended: "disabled" (default: call batchReset),
   * "same_step" (reset within the step; its last observation is final_observation) or
   * "next_step" (Gymnasium's: reset on the next step, whose action for it is ignored). */
  autoreset?: AutoresetName;
}

/** A batch handle, as batchCreateEnvs returned it. */
export interface BatchIdJson {
  /** e.g. "batch_1". */
  batch_id: string;
}

/** One env's part of `batchStep`'s result. */
export interface EnvStepJson {
  /** The env's index in the batch (0-based; the order of the action arrays). */
  env_index: number;
  observation: ObservationJson;
  reward: number;
  done: boolean;
  terminated: boolean;
  truncated: boolean;
  termination_reason?: string;
  /** With same_step autoreset: the last observation of the episode that just ended. */
  final_observation?: ObservationJson;
  terms?: Record<string, number>;
}

/** What `batchStep` returns: one entry per env, env 0 first. */
export interface BatchStepJson {
  batch_id: string;
  results: EnvStepJson[];
}

/** What `batchReset` returns: one observation per env, env 0 first. */
export interface BatchObservationsJson {
  batch_id: string;
  observations: ObservationJson[];
}

/** What `batchClose` returns. */
export interface BatchClosedJson {
  batch_id: string;
  /** Always true. */
  closed: true;
}

/** A batch's observations, packed. */
export interface PackedObservations {
  batch_id: string;
  n_envs: number;
  observation_dim: number;
  /** n_envs × observation_dim floats, row-major: env i's row is
   * `observations.subarray(i * observation_dim, (i + 1) * observation_dim)`, laid out as
   * the batch's observation_layout says (positions, velocities, poses, task). */
  observations: Float32Array;
}

/** A batch step's outcome, packed. */
export interface PackedBatchStep extends PackedObservations {
  /** Batch steps since the batch was created, this one included. */
  step_index: number;
  /** One per env. */
  rewards: Float32Array;
  terminated: boolean[];
  truncated: boolean[];
  /** Same-step autoreset: the envs that finished and were reset in this step. */
  final_env_indices: number[];
  /** Their last observations, one row each, in final_env_indices order. */
  final_observations: Float32Array;
  /** Env index → why it terminated in this step, for envs with a reason. */
  termination_reasons: Record<number, string>;
  /** A terms task's values, n_envs × (number of terms), row-major. */
  terms: Float32Array;
  /** The envs whose rows these are, when the step listed some (`env_indices`); empty:
   * every env, in order. Final indices and termination reasons name batch indices. */
  env_indices: number[];
}

function plural(n: number, word: string): string {
  return `${n} ${word}${n === 1 ? "" : "s"}`;
}

/** The record of a batch this client created: its layout cuts rows into the guide's
 * observations. */
function batchInfo(client: GymfleetClient, batchId: string): BatchInfo {
  const batches = known(client).batches;
  const info = batches.get(batchId);
  if (info === undefined) {
    const open = [...batches.keys()].join(", ") || "none";
    throw new NotFound(
      `unknown batch_id ${JSON.stringify(batchId)}: this client has no open batch with this id ` +
        `(open: ${open}). Create one with batchCreateEnvs; batchStepPacked and ` +
        "batchResetPacked take any batch of the server.",
      Code.NotFound,
    );
  }
  return info;
}

/** Creates n_envs identical environments, stepped together in parallel. */
export async function batchCreateEnvs(
  params: CreateBatchParams,
  client: GymfleetClient = defaultClient(),
): Promise<BatchCreatedJson> {
  const request = {
    options: createFields(params),
    nEnvs: params.n_envs,
    autoreset: autoreset(params.autoreset),
  };
  const info = await client.simulator.createBatch(request);
  known(client).batches.set(info.batchId, info);
  return fromBatchInfo(info);
}

/** Steps every env once: `actions` holds one array per env (n_envs arrays, env 0
 * first), each of action_dim values. Results are grouped by env. */
export async function batchStep(
  params: BatchIdJson & { action_type: ActionTypeName; actions: ArrayLike<ArrayLike<number>> },
  client: GymfleetClient = defaultClient(),
): Promise<BatchStepJson> {
  const info = batchInfo(client, params.batch_id);
  const type = actionType(params.action_type);
  const { nEnvs } = info;
  const { actionDim, observationLayout: layout, termNames } = batchEnv(info);
  const rows = params.actions;
  const shape = `${params.batch_id} expects ${plural(nEnvs, "array")} of ${plural(actionDim, "value")}`;
  if (rows.length !== nEnvs) {
    throw invalid(
      `${shape} (one array per env, action_dim values each); got ${plural(rows.length, "array")}`,
      "INVALID_ACTION",
    );
  }
  const flat: number[] = [];
  for (let env = 0; env < nEnvs; env++) {
    if (rows[env]!.length !== actionDim) {
      throw invalid(`${shape}; array ${env} has ${rows[env]!.length}`, "INVALID_ACTION");
    }
  }
  for (let env = 0; env < nEnvs; env++) {
    pushActionValues(flat, rows[env]!, `actions[${env}]`);
  }
  const step = await stepPacked(client, params.batch_id, type, flat);
  const dim = step.observation_dim;
  const k = termNames.length;
  const results = Array.from({ length: step.n_envs }, (_, env): EnvStepJson => {
    const terminated = step.terminated[env]!;
    const truncated = step.truncated[env]!;
    const out: EnvStepJson = {
      env_index: env,
      observation: fromRow(step.observations.subarray(env * dim, (env + 1) * dim), layout),
      reward: clean(step.rewards[env]!),
      done: terminated || truncated,
      terminated,
      truncated,
    };
    const reason = step.termination_reasons[env];
    if (reason !== undefined) out.termination_reason = reason;
    const final = step.final_env_indices.indexOf(env);
    if (final >= 0) {
      out.final_observation = fromRow(
        step.final_observations.subarray(final * dim, (final + 1) * dim),
        layout,
      );
    }
    const named = terms(termNames, step.terms.subarray(env * k, (env + 1) * k));
    if (named !== undefined) out.terms = named;
    return out;
  });
  return { batch_id: params.batch_id, results };
}

/** Resets every env (with `seed`: env i reseeded with seed + i first); one observation
 * per env. */
export async function batchReset(
  params: BatchIdJson & { seed?: number | bigint },
  client: GymfleetClient = defaultClient(),
): Promise<BatchObservationsJson> {
  const layout = batchInfo(client, params.batch_id).observationLayout;
  const packed = await batchResetPacked(params, client);
  const dim = packed.observation_dim;
  const observations = Array.from({ length: packed.n_envs }, (_, env) =>
    fromRow(packed.observations.subarray(env * dim, (env + 1) * dim), layout),
  );
  return { batch_id: params.batch_id, observations };
}

/** Closes a batch and frees all its envs. */
export async function batchClose(
  params: BatchIdJson,
  client: GymfleetClient = defaultClient(),
): Promise<BatchClosedJson> {
  await client.simulator.closeBatch({ batchId: params.batch_id });
  known(client).batches.delete(params.batch_id);
  return { batch_id: params.batch_id, closed: true };
}

function packed(o: BatchObservation): PackedObservations {
  return {
    batch_id: o.batchId,
    n_envs: o.nEnvs,
    observation_dim: o.observationDim,
    observations: Float32Array.from(o.observations),
  };
}

async function stepPacked(
  client: GymfleetClient,
  batchId: string,
  type: ReturnType<typeof actionType>,
  actions: number[],
  envIndices: number[] = [],
): Promise<PackedBatchStep> {
  return packedStep(await client.simulator.stepBatch({ batchId, actionType: type, actions, envIndices }));
}

/** A `BatchStepResult` as a {@link PackedBatchStep} (unary and streamed steps alike). */
export function packedStep(r: BatchStepResult): PackedBatchStep {
  const nEnvs = r.rewards.length;
  return {
    batch_id: r.batchId,
    n_envs: nEnvs,
    observation_dim: nEnvs === 0 ? 0 : r.observations.length / nEnvs,
    observations: Float32Array.from(r.observations),
    step_index: Number(r.stepIndex),
    rewards: Float32Array.from(r.rewards),
    terminated: r.terminated,
    truncated: r.truncated,
    final_env_indices: r.finalEnvIndices,
    final_observations: Float32Array.from(r.finalObservations),
    termination_reasons: r.terminationReasons,
    terms: Float32Array.from(r.terms),
    env_indices: r.envIndices,
  };
}

/** Steps every env once with n_envs × action_dim values, row-major (env 0's action
 * first), and returns the packed outcome. Works on any batch of the server. With
 * `env_indices` (ascending, distinct), only those envs step, one action row each in that
 * order, each exactly as in a whole step; the result has their rows (an asynchronous
 * trainer's send). */
export async function batchStepPacked(
  params: BatchIdJson & {
    action_type: ActionTypeName;
    actions: ArrayLike<number>;
    env_indices?: number[];
  },
  client: GymfleetClient = defaultClient(),
): Promise<PackedBatchStep> {
  const type = actionType(params.action_type);
  const flat: number[] = [];
  pushActionValues(flat, params.actions, "actions");
  return stepPacked(client, params.batch_id, type, flat, params.env_indices ?? []);
}

/** Resets every env, or only `env_indices` (ascending, e.g. the ones that ended; the
 * others keep their state), and returns every env's observation, packed. */
export async function batchResetPacked(
  params: BatchIdJson & { seed?: number | bigint; env_indices?: number[]; keyframe?: string },
  client: GymfleetClient = defaultClient(),
): Promise<PackedObservations> {
  const request = {
    batchId: params.batch_id,
    seed: seed(params.seed),
    envIndices: params.env_indices ?? [],
    keyframe: params.keyframe ?? "",
  };
  return packed(await client.simulator.resetBatch(request));
}

/** Every env's current observation, packed, without stepping. */
export async function batchObservePacked(
  params: BatchIdJson,
  client: GymfleetClient = defaultClient(),
): Promise<PackedObservations> {
  return packed(await client.simulator.observeBatch({ batchId: params.batch_id }));
}
