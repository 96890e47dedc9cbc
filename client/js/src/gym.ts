/**
 * The user guide's single-environment tools as functions, camelCased: `createRobotEnv`,
 * `gymReset`, `gymStep`, `gymObserve`, `gymClose`, and the MCP adapter's `gymRender`,
 * `gymSaveState`, `gymLoadState` and `listModels`. Each takes and returns the guide's JSON
 * (snake_case keys, document units, `env_id` handles), as the MCP tools do, and calls the
 * server given as `client` (default: {@link defaultClient}, from `GYMFLEET_SERVER`).
 */

import { type GymfleetClient, defaultClient } from "./client.js";
import { DocumentFormat } from "./gen/gymfleet/v1/simulator_pb.js";
import { known } from "./known.js";
import {
  actionType,
  base64,
  cameraPreset,
  createFields,
  pushActionValues,
  seed,
  type ActionTypeName,
  type CameraName,
  type CreateEnvParams,
} from "./params.js";
import {
  clean,
  fromEnvInfo,
  fromObservation,
  fromStep,
  type EnvCreatedJson,
  type ObservationJson,
  type StepJson,
} from "./shapes.js";

/** An env handle, as createRobotEnv returned it. */
export interface EnvIdJson {
  /** e.g. "sim_1". */
  env_id: string;
}

/** What `gymClose` returns. */
export interface EnvClosedJson {
  env_id: string;
  /** Always true. */
  closed: true;
}

/** The inputs of `gymRender`. */
export interface RenderParams extends EnvIdJson {
  /** Viewing direction, framing the whole robot: "iso" (default), "front", "side", "top". */
  camera?: CameraName;
  /** Camera position `[x, y, z]`, world mm (overrides the preset's direction). */
  eye?: [number, number, number];
  /** Point looked at `[x, y, z]`, world mm (default: the robot's centre). */
  target?: [number, number, number];
  /** Vertical field of view, degrees, (0, 170]; default 45. */
  fov_deg?: number;
  /** Parallel projection instead of perspective. */
  orthographic?: boolean;
  /** Pixels, 16 to 2048 (default 320 × 240). */
  width?: number;
  height?: number;
}

/** What `gymRender` returns: the MCP tool's JSON, plus the picture. */
export interface RenderJson {
  env_id: string;
  width: number;
  height: number;
  /** Distance between two ground-grid lines, mm (every fifth line darker). */
  grid_mm: number;
  /** What the picture shows: camera, grid, marker colours, positions. */
  description: string;
  /** An 8-bit RGB PNG file. */
  png: Uint8Array;
}

/** What `gymSaveState` returns. */
export interface StateSavedJson {
  env_id: string;
  /** The whole state, base64: give it to gymLoadState to return to this moment. */
  state: string;
  /** The state's size in bytes (before base64). */
  bytes: number;
}

/** One model of the server's library. */
export interface ModelJson {
  /** The name to give createRobotEnv or batchCreateEnvs as `model`. */
  name: string;
  /** "json", "mjcf" or "urdf". */
  format: string;
  dofs: number;
  action_dim: number;
}

const FORMATS: Partial<Record<DocumentFormat, string>> = {
  [DocumentFormat.MJCF]: "mjcf",
  [DocumentFormat.URDF]: "urdf",
};

function vec3(v: [number, number, number] | undefined) {
  return v === undefined ? undefined : { x: v[0], y: v[1], z: v[2] };
}

/** Creates one physics environment from an assembly document (or a library model). */
export async function createRobotEnv(
  params: CreateEnvParams,
  client: GymfleetClient = defaultClient(),
): Promise<EnvCreatedJson> {
  const info = await client.simulator.createEnv({ options: createFields(params) });
  known(client).envs.set(info.envId, info.termNames);
  return fromEnvInfo(info);
}

/** Resets an env to its initial state (with `seed`: reseeded first; with `keyframe`: from
 * that one of the document's keyframes, the reset noise on top) and returns the first
 * observation. */
export async function gymReset(
  params: EnvIdJson & { seed?: number | bigint; keyframe?: string },
  client: GymfleetClient = defaultClient(),
): Promise<ObservationJson> {
  const observation = await client.simulator.reset({
    envId: params.env_id,
    seed: seed(params.seed),
    keyframe: params.keyframe ?? "",
  });
  return fromObservation(observation);
}

/** Applies one action (action_dim values, in the unit of `action_type`) for one step of
 * dt seconds. */
export async function gymStep(
  params: EnvIdJson & { action_type: ActionTypeName; values: ArrayLike<number> },
  client: GymfleetClient = defaultClient(),
): Promise<StepJson> {
  const values: number[] = [];
  const type = actionType(params.action_type);
  pushActionValues(values, params.values, "values");
  const result = await client.simulator.step({ envId: params.env_id, actionType: type, values });
  return fromStep(result, known(client).envs.get(params.env_id) ?? []);
}

/** Sets where mocap body `body` (one of `mocap_bodies`) is to be at the end of the next
 * step, and stay: `position` `[x, y, z]` in world mm, `quaternion` `[qw, qx, qy, qz]`
 * (default no rotation). What is welded to it follows; what it touches is pushed. */
export async function gymSetMocapPose(
  params: EnvIdJson & {
    body: string;
    position: [number, number, number];
    quaternion?: [number, number, number, number];
  },
  client: GymfleetClient = defaultClient(),
): Promise<Record<string, never>> {
  const pose = [...params.position, ...(params.quaternion ?? [1, 0, 0, 0])];
  await client.simulator.setMocapPose({ envId: params.env_id, body: params.body, pose });
  return {};
}

/** The current observation, without stepping. */
export async function gymObserve(
  params: EnvIdJson,
  client: GymfleetClient = defaultClient(),
): Promise<ObservationJson> {
  return fromObservation(await client.simulator.observe({ envId: params.env_id }));
}

/** Closes an env; any later call on its id is NotFound. */
export async function gymClose(
  params: EnvIdJson,
  client: GymfleetClient = defaultClient(),
): Promise<EnvClosedJson> {
  await client.simulator.close({ envId: params.env_id });
  known(client).envs.delete(params.env_id);
  return { env_id: params.env_id, closed: true };
}

/** A PNG picture of an env as it is now. */
export async function gymRender(
  params: RenderParams,
  client: GymfleetClient = defaultClient(),
): Promise<RenderJson> {
  const sized = params.width !== undefined || params.height !== undefined;
  const preset = cameraPreset(params.camera);
  const image = await client.simulator.render({
    envId: params.env_id,
    camera: {
      preset,
      eye: vec3(params.eye),
      target: vec3(params.target),
      fovDeg: params.fov_deg ?? 0,
      orthographic: params.orthographic ?? false,
    },
    width: sized ? (params.width ?? 320) : 0,
    height: sized ? (params.height ?? 240) : 0,
  });
  return {
    env_id: params.env_id,
    width: image.width,
    height: image.height,
    grid_mm: clean(image.gridMm),
    description: image.description,
    png: image.png,
  };
}

/** Saves an env's whole state (pose, velocities, episode, task target, generator). */
export async function gymSaveState(
  params: EnvIdJson,
  client: GymfleetClient = defaultClient(),
): Promise<StateSavedJson> {
  const { state } = await client.simulator.saveState({ envId: params.env_id });
  return { env_id: params.env_id, state: Buffer.from(state).toString("base64"), bytes: state.length };
}

/** Returns an env (of the same document and options) to a state gymSaveState returned. */
export async function gymLoadState(
  params: EnvIdJson & { state: string },
  client: GymfleetClient = defaultClient(),
): Promise<ObservationJson> {
  const state = base64(params.state, "state", "the base64 text gymSaveState returns");
  return fromObservation(await client.simulator.loadState({ envId: params.env_id, state }));
}

/** The server's model library (`--models DIR`): names to give as `model`. */
export async function listModels(client: GymfleetClient = defaultClient()): Promise<{ models: ModelJson[] }> {
  const { models } = await client.simulator.listModels({});
  return {
    models: models.map((m) => ({
      name: m.name,
      format: FORMATS[m.format] ?? "json",
      dofs: m.dofs,
      action_dim: m.actionDim,
    })),
  };
}
