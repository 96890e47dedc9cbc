/**
 * The gym functions' outputs: the user guide's JSON, exactly as the MCP adapter's tools
 * return it (`apps/mcp/src/output.rs`): snake_case keys in the guide's order, and each
 * float of the wire (32-bit) given as the number with the same shortest decimal form
 * ({@link clean}), so a pose prints as `10.042`, not `10.041999816894531`.
 */

import { create } from "@bufbuild/protobuf";

import {
  Autoreset,
  EnvInfoSchema,
  ObservationSchema,
  type ActuatorInfo,
  type BatchInfo,
  type EnvInfo,
  type JointInfo,
  type Observation,
  type ObservationSegment,
  type StepResult,
} from "./gen/gymfleet/v1/simulator_pb.js";

/** Floats per pose: `[x, y, z, qw, qx, qy, qz]`. */
export const POSE_LEN = 7;

/** One environment's observation. */
export interface ObservationJson {
  /** Per DOF in document joint order: degrees (revolute) or mm (prismatic); measured. */
  joint_positions: number[];
  /** Per DOF: degrees/s or mm/s. */
  joint_velocities: number[];
  /** One `[x, y, z, qw, qx, qy, qz]` per end effector: centre of mass in world mm, then
   * the world orientation as a unit quaternion. */
  end_effector_poses: number[][];
  /** With a reach task only: the target `[x, y, z]` in world mm. */
  target?: number[];
  /** With a floating base only: its `[x, y, z, qw, qx, qy, qz]`. */
  base_pose?: number[];
  /** With a floating base only: `[vx, vy, vz]` mm/s, then `[wx, wy, wz]` deg/s. */
  base_velocity?: number[];
  /** With free bodies only (objects, in `free_bodies` order): each one's `[x, y, z, qw,
   * qx, qy, qz]`, its frame's origin in world mm and its orientation. */
  free_body_poses?: number[][];
  /** With free bodies only: each one's `[vx, vy, vz]` mm/s in the world, then `[wx, wy,
   * wz]` deg/s in its own axes. */
  free_body_velocities?: number[][];
}

/** The limits of one DOF. */
export interface DofLimitJson {
  /** "deg" or "mm". */
  unit: string;
  /** Lower hard stop in that unit, or null for none. */
  min: number | null;
  /** Upper hard stop in that unit, or null for none. */
  max: number | null;
}

/** One non-fixed joint. */
export interface JointJson {
  name: string;
  /** "revolute", "prismatic", "cylindrical" or "ball". */
  type: string;
  /** DOFs (action values) it contributes. */
  dof: number;
  parent: string;
  child: string;
  /** One entry per DOF. */
  limits: DofLimitJson[];
  /** One per DOF: the largest sensible torque action value (N·m, or N for a linear DOF). */
  torque_bounds: number[];
}

/** What `createRobotEnv` returns. */
export interface EnvCreatedJson {
  /** The handle of every other env call, e.g. "sim_1". */
  env_id: string;
  num_joints: number;
  /** Values per action. */
  action_dim: number;
  observation_dim: number;
  end_effector_ids: string[];
  /** Seconds per step. */
  dt: number;
  substeps: number;
  max_steps: number;
  /** The non-fixed joints in document order (the DOF order of actions and observations). */
  joints: JointJson[];
  /** Objects that move freely, observed as `free_body_poses` and `free_body_velocities`
   * (only when there are any). */
  free_bodies?: string[];
  /** Mocap bodies: kinematic handles `gymSetMocapPose` moves (only when there are any). */
  mocap_bodies?: string[];
  /** Actuators (only when there are any): the action's last values are their controls,
   * in this order. */
  actuators?: ActuatorJson[];
  /** The document's keyframes (only when there are any): what `gymReset`'s `keyframe` may
   * name. */
  keyframes?: string[];
}

/** One actuator (a converted MJCF's `<actuator>`). */
export interface ActuatorJson {
  name: string;
  /** Its kind as written ("motor", "position", …; a converted MJCF's: "general"). */
  type: string;
  /** The joint or fixed tendon it drives. */
  target: string;
  /** Controls are clamped into `[min, max]` (MuJoCo's ctrlrange); absent: unclamped. */
  ctrl_range?: [number, number];
}

/** What `gymStep` returns. */
export interface StepJson {
  observation: ObservationJson;
  /** The task's reward; 0 without a task. */
  reward: number;
  /** terminated || truncated: the episode is over; call gymReset. */
  done: boolean;
  terminated: boolean;
  truncated: boolean;
  /** Why it terminated, when it did: "goal_reached", "fell", "physics_diverged", … */
  termination_reason?: string;
  /** A terms task's values for the step, by term name (sorted by name). */
  terms?: Record<string, number>;
}

/** What `batchCreateEnvs` returns. */
export interface BatchCreatedJson {
  /** The handle of every other batch call, e.g. "batch_1". */
  batch_id: string;
  n_envs: number;
  action_dim: number;
  observation_dim: number;
  num_joints: number;
  end_effector_ids: string[];
  dt: number;
  substeps: number;
  max_steps: number;
  /** "disabled", "same_step" or "next_step". */
  autoreset: string;
  joints: JointJson[];
  /** As `EnvCreatedJson.actuators`. */
  actuators?: ActuatorJson[];
  /** As `EnvCreatedJson.keyframes`. */
  keyframes?: string[];
}

/** `x` (a 32-bit float) as the number with the same shortest decimal form: the shortest
 * decimal that reads back as the same 32-bit float, as Rust prints an `f32`. */
export function clean(x: number): number {
  if (!Number.isFinite(x) || x === 0) {
    return x;
  }
  for (let digits = 1; digits < 9; digits++) {
    const shorter = Number(x.toPrecision(digits));
    if (Math.fround(shorter) === x) {
      return shorter;
    }
  }
  return Number(x.toPrecision(9));
}

function cleanAll(xs: ArrayLike<number>): number[] {
  return Array.from(xs, clean);
}

/** `values` cut into poses of {@link POSE_LEN}. */
function poses(values: ArrayLike<number>): number[][] {
  const out: number[][] = [];
  for (let at = 0; at + POSE_LEN <= values.length; at += POSE_LEN) {
    out.push(Array.from({ length: POSE_LEN }, (_, k) => clean(values[at + k]!)));
  }
  return out;
}

/** The guide's observation, the optional parts added only when present. */
function observationJson(
  positions: ArrayLike<number>,
  velocities: ArrayLike<number>,
  eePoses: ArrayLike<number>,
  task: ArrayLike<number>,
  basePose: ArrayLike<number>,
  baseVelocity: ArrayLike<number>,
  freePoses: ArrayLike<number>,
  freeVelocities: ArrayLike<number>,
): ObservationJson {
  const out: ObservationJson = {
    joint_positions: cleanAll(positions),
    joint_velocities: cleanAll(velocities),
    end_effector_poses: poses(eePoses),
  };
  if (task.length === 3) {
    out.target = cleanAll(task);
  }
  if (basePose.length === POSE_LEN && baseVelocity.length === 6) {
    out.base_pose = cleanAll(basePose);
    out.base_velocity = cleanAll(baseVelocity);
  }
  if (freePoses.length > 0) {
    out.free_body_poses = rows(freePoses, POSE_LEN);
    out.free_body_velocities = rows(freeVelocities, 6);
  }
  return out;
}

/** `values` cut into rows of `width`, each cleaned. */
function rows(values: ArrayLike<number>, width: number): number[][] {
  const all = Array.from(values);
  const out: number[][] = [];
  for (let at = 0; at + width <= all.length; at += width) {
    out.push(cleanAll(all.slice(at, at + width)));
  }
  return out;
}

/** A single env's observation message as the guide's JSON. */
export function fromObservation(o: Observation): ObservationJson {
  return observationJson(
    o.jointPositions,
    o.jointVelocities,
    o.endEffectorPoses,
    o.taskObservation,
    o.basePose,
    o.baseVelocity,
    o.freeBodyPoses,
    o.freeBodyVelocities,
  );
}

/** One row of a batch's packed observations, cut by the batch's observation layout. */
export function fromRow(row: Float32Array, layout: ObservationSegment[]): ObservationJson {
  const segments = new Map<string, Float32Array>();
  let at = 0;
  for (const { name, size } of layout) {
    segments.set(name, row.subarray(at, at + size));
    at += size;
  }
  const none = new Float32Array(0);
  const part = (name: string) => segments.get(name) ?? none;
  return observationJson(
    part("joint_positions"),
    part("joint_velocities"),
    part("end_effector_poses"),
    part("target"),
    part("base_pose"),
    part("base_velocity"),
    part("free_body_poses"),
    part("free_body_velocities"),
  );
}

/** A terms task's values by name, or `undefined` without one. */
export function terms(names: string[], values: ArrayLike<number>): Record<string, number> | undefined {
  if (names.length === 0 || values.length === 0) {
    return undefined;
  }
  const sorted = names.map((name, i) => [name, clean(values[i] ?? 0)] as const);
  sorted.sort(([a], [b]) => (a < b ? -1 : a > b ? 1 : 0));
  return Object.fromEntries(sorted);
}

/** A single env's step result as the guide's JSON. */
export function fromStep(r: StepResult, termNames: string[]): StepJson {
  const out: StepJson = {
    observation: fromObservation(r.observation ?? create(ObservationSchema)),
    reward: clean(r.reward),
    done: r.done,
    terminated: r.terminated,
    truncated: r.truncated,
  };
  if (r.terminationReason !== undefined) {
    out.termination_reason = r.terminationReason;
  }
  const named = terms(termNames, r.terms);
  if (named !== undefined) {
    out.terms = named;
  }
  return out;
}

function joints(list: JointInfo[]): JointJson[] {
  return list.map((j) => ({
    name: j.name,
    type: j.type,
    dof: j.dof,
    parent: j.parent,
    child: j.child,
    limits: j.limits.map((l) => ({ unit: l.unit, min: l.min ?? null, max: l.max ?? null })),
    torque_bounds: [...j.actionBounds],
  }));
}

/** What `createRobotEnv` returns, from the server's EnvInfo. */
export function fromEnvInfo(i: EnvInfo): EnvCreatedJson {
  const out: EnvCreatedJson = {
    env_id: i.envId,
    num_joints: i.numJoints,
    action_dim: i.actionDim,
    observation_dim: i.observationDim,
    end_effector_ids: [...i.endEffectorIds],
    dt: i.dt,
    substeps: i.substeps,
    max_steps: i.maxSteps,
    joints: joints(i.joints),
  };
  if (i.freeBodies.length > 0) {
    out.free_bodies = [...i.freeBodies];
  }
  if (i.mocapBodies.length > 0) {
    out.mocap_bodies = [...i.mocapBodies];
  }
  if (i.actuators.length > 0) {
    out.actuators = actuators(i.actuators);
  }
  if (i.keyframes.length > 0) {
    out.keyframes = [...i.keyframes];
  }
  return out;
}

function actuators(list: ActuatorInfo[]): ActuatorJson[] {
  return list.map((a) => {
    const out: ActuatorJson = { name: a.name, type: a.type, target: a.target };
    if (a.ctrlMin !== undefined && a.ctrlMax !== undefined) {
      out.ctrl_range = [a.ctrlMin, a.ctrlMax];
    }
    return out;
  });
}

/** The guide's name of an autoreset mode. */
export const AUTORESET_NAMES: Record<Autoreset, string> = {
  [Autoreset.DISABLED]: "disabled",
  [Autoreset.SAME_STEP]: "same_step",
  [Autoreset.NEXT_STEP]: "next_step",
};

/** What every env of a batch is: the BatchInfo's `env` (from a server that sends only
 * the deprecated flat fields, those). */
export function batchEnv(i: BatchInfo): EnvInfo {
  return (
    i.env ??
    create(EnvInfoSchema, {
      numJoints: i.numJoints,
      actionDim: i.actionDim,
      observationDim: i.observationDim,
      endEffectorIds: i.endEffectorIds,
      dt: i.dt,
      substeps: i.substeps,
      maxSteps: i.maxSteps,
      joints: i.joints,
      observationLayout: i.observationLayout,
      units: i.units,
      termNames: i.termNames,
      freeBodies: i.freeBodies,
      mocapBodies: i.mocapBodies,
      movingMass: i.movingMass,
      actuators: i.actuators,
      keyframes: i.keyframes,
      heightfields: i.heightfields,
    })
  );
}

/** What `batchCreateEnvs` returns, from the server's BatchInfo. */
export function fromBatchInfo(i: BatchInfo): BatchCreatedJson {
  const e = batchEnv(i);
  const out: BatchCreatedJson = {
    batch_id: i.batchId,
    n_envs: i.nEnvs,
    action_dim: e.actionDim,
    observation_dim: e.observationDim,
    num_joints: e.numJoints,
    end_effector_ids: [...e.endEffectorIds],
    dt: e.dt,
    substeps: e.substeps,
    max_steps: e.maxSteps,
    autoreset: AUTORESET_NAMES[i.autoreset],
    joints: joints(e.joints),
  };
  if (e.actuators.length > 0) {
    out.actuators = actuators(e.actuators);
  }
  if (e.keyframes.length > 0) {
    out.keyframes = [...e.keyframes];
  }
  return out;
}
