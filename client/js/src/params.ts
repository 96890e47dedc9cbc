/**
 * The gym functions' inputs: the user guide's JSON, the MCP tools' arguments
 * (`apps/mcp/src/params.rs`, `task.rs`), and their checks before any call: the
 * document, a task, randomisation, action types and values, seeds and base64 text.
 */

import type { MessageInitShape } from "@bufbuild/protobuf";

import { invalid } from "./errors.js";
import { ActionType, Autoreset, CameraPreset, type TaskSchema } from "./gen/gymfleet/v1/simulator_pb.js";

/** An assembly document: a JSON object, or text (JSON, MuJoCo MJCF or ROS URDF). */
export type Document = { [key: string]: unknown } | string;

/** A point or offset, mm. */
export interface Vec3Json {
  x: number;
  y: number;
  z: number;
}

/** Reach: bring a point of an instance to a target; reward = minus the distance in mm. */
export interface ReachJson {
  /** The instance carrying the point, e.g. "forearm". */
  end_effector: string;
  /** The point in that instance's frame, mm. Default: its centre of mass. */
  point?: Vec3Json;
  /** A fixed target, world mm. Give this or target_box. */
  target?: Vec3Json;
  /** A box from which a new target is drawn at every reset (seeded), world mm. */
  target_box?: { min: Vec3Json; max: Vec3Json };
  /** The goal is reached within this distance, mm. Default 0: never. */
  success_radius?: number;
  /** End the episode ("goal_reached") when the goal is reached. */
  terminate_on_success?: boolean;
}

/** Track: hold every DOF at its target; reward = minus the error norm (deg or mm). */
export interface TrackJson {
  /** One target per DOF, degrees or mm. */
  targets: number[];
  /** The goal is reached within this error norm. Default 0: never. */
  tolerance?: number;
  terminate_on_success?: boolean;
}

/** Upright: keep an instance's axis near world +Z; +1 per step; "fell" past the tilt. */
export interface UprightJson {
  instance: string;
  /** The axis in the instance's frame. Default +Z. */
  axis?: Vec3Json;
  /** Largest tilt from vertical, degrees, in (0, 180). */
  max_tilt_deg: number;
}

/** What the env is asked to do: exactly one of reach, track, upright and terms. */
export interface TaskJson {
  reach?: ReachJson;
  track?: TrackJson;
  upright?: UprightJson;
  /** A terms task: `{"terms": [...], "healthy": {...}, "reset_noise": {...}}` (the
   * docs/tasks.md, "Terms tasks"). */
  terms?: { [key: string]: unknown };
  /** Subtracted from each step's reward: this weight × Σ a². Default 0. */
  action_cost?: number;
}

/** A range of scale factors, 0 < min <= max <= 100. */
export interface RangeJson {
  min: number;
  max: number;
}

/** Domain randomisation: factors drawn at every reset (seeded). */
export interface RandomizeJson {
  mass_scale?: RangeJson;
  friction_scale?: RangeJson;
  damping_scale?: RangeJson;
  gain_scale?: RangeJson;
}

/** The inputs of `createRobotEnv`. Unset options take the server's defaults. */
export interface CreateEnvParams {
  /** The assembly document. Give this or `model`. */
  document?: Document;
  /** Instead of a document: a model of the server's library (see listModels). */
  model?: string;
  /** The mesh files the document references, as one zip, tar or tar.gz archive in base64. */
  assets_base64?: string;
  /** Instance names whose poses are observed, in this order. Default: none. */
  end_effector_ids?: string[];
  /** Seconds of simulated time per step. Default 1/240. */
  dt?: number;
  /** Integration substeps per step. Default 5. */
  substeps?: number;
  /** Episode length in steps. Default 1000. */
  max_steps?: number;
  /** Seed of the env's random generator: a non-negative safe integer, or a bigint below
   * 2^64. Default 0. */
  seed?: number | bigint;
  /** PD gain overrides per DOF, SI units (N·m/rad, N·m·s/rad; N/m, N·s/m). */
  pd_gains?: { kp?: number[]; kd?: number[] };
  /** Every reset offsets each DOF by a value drawn from [-reset_noise, +reset_noise],
   * degrees or mm. Default 0. */
  reset_noise?: number;
  task?: TaskJson;
  randomize?: RandomizeJson;
}

/** The guide's action types. */
export type ActionTypeName = "torque" | "position" | "velocity";
/** The MCP tool gym_render's camera presets. */
export type CameraName = "iso" | "front" | "side" | "top";
/** The guide's autoreset modes. */
export type AutoresetName = "disabled" | "same_step" | "next_step";

const ACTION_TYPES: Record<ActionTypeName, ActionType> = {
  torque: ActionType.TORQUE,
  position: ActionType.POSITION,
  velocity: ActionType.VELOCITY,
};

const CAMERAS: Record<CameraName, CameraPreset> = {
  iso: CameraPreset.ISO,
  front: CameraPreset.FRONT,
  side: CameraPreset.SIDE,
  top: CameraPreset.TOP,
};

const AUTORESETS: Record<AutoresetName, Autoreset> = {
  disabled: Autoreset.DISABLED,
  same_step: Autoreset.SAME_STEP,
  next_step: Autoreset.NEXT_STEP,
};

/** `value` as one of `names`' values, or an error listing them. */
function oneOf<T>(field: string, names: Record<string, T>, value: unknown): T {
  if (typeof value === "string" && Object.hasOwn(names, value)) {
    return names[value]!;
  }
  const keys = Object.keys(names).map((k) => JSON.stringify(k));
  const expected = `${keys.slice(0, -1).join(", ")} or ${keys[keys.length - 1]}`;
  throw invalid(`${field}: expected ${expected}, got ${JSON.stringify(value)}`);
}

/** The wire's action type for the guide's name. */
export function actionType(value: unknown): ActionType {
  return oneOf("action_type", ACTION_TYPES, value);
}

/** The wire's autoreset mode for the guide's name (default "disabled"). */
export function autoreset(value: unknown): Autoreset {
  return value === undefined ? Autoreset.DISABLED : oneOf("autoreset", AUTORESETS, value);
}

/** The wire's camera preset for gym_render's name (default "iso"). */
export function cameraPreset(value: unknown): CameraPreset {
  return value === undefined ? CameraPreset.ISO : oneOf("camera", CAMERAS, value);
}

/** A seed as the wire's uint64. */
export function seed(value: number | bigint | undefined): bigint | undefined {
  if (value === undefined) {
    return undefined;
  }
  const ok =
    typeof value === "bigint" ? value >= 0n && value < 1n << 64n : Number.isSafeInteger(value) && value >= 0;
  if (!ok) {
    throw invalid(`seed: expected a non-negative safe integer, or a bigint below 2^64; got ${String(value)}`);
  }
  return BigInt(value);
}

/** Base64 text as bytes, or an error naming `what` it should be. */
export function base64(text: string, field: string, what: string): Uint8Array {
  const trimmed = text.trim();
  if (trimmed.length % 4 !== 0 || !/^[A-Za-z0-9+/]*={0,2}$/.test(trimmed)) {
    throw invalid(`${field}: not ${what}`);
  }
  return Buffer.from(trimmed, "base64");
}

/** What `value` is, in words: "null", "an array", "the string \"0.5\"", "a boolean". */
function describe(value: unknown): string {
  if (value === null) return "null";
  if (Array.isArray(value)) return "an array";
  if (typeof value === "string") return `the string ${JSON.stringify(value)}`;
  return typeof value === "object" ? "an object" : `a ${typeof value}`;
}

/** Why `v` is not a finite 32-bit float, or `undefined` if it is one. */
function notFinite(v: unknown): string | undefined {
  if (v === null || v === undefined) return `is ${String(v)}`;
  if (typeof v !== "number") return `is ${describe(v)}, not a number`;
  if (Number.isNaN(v)) return "is NaN";
  if (!Number.isFinite(v)) return `is infinite (${v > 0 ? "inf" : "-inf"})`;
  if (!Number.isFinite(Math.fround(v))) {
    return `= ${v.toExponential()} is out of range (actions are 32-bit floats, at most about 3.4e38)`;
  }
  return undefined;
}

/** Checks action values (`path` names them, e.g. "values" or "actions[3]") and appends
 * them to `out`. */
export function pushActionValues(out: number[], values: ArrayLike<unknown>, path: string): void {
  for (let i = 0; i < values.length; i++) {
    const why = notFinite(values[i]);
    if (why !== undefined) {
      throw invalid(`${path}[${i}] ${why}; every action value must be a finite number`, "INVALID_ACTION");
    }
    out.push(values[i] as number);
  }
}

function vec3(v: Vec3Json | undefined) {
  return v === undefined ? undefined : { x: v.x, y: v.y, z: v.z };
}

/** The wire's task. */
function task(t: TaskJson): MessageInitShape<typeof TaskSchema> {
  const given = (["reach", "track", "upright", "terms"] as const).filter((k) => t[k] !== undefined);
  if (given.length !== 1) {
    throw invalid('task: give exactly one of "reach", "track", "upright" or "terms"');
  }
  const actionCost = t.action_cost ?? 0;
  if (t.reach) {
    const r = t.reach;
    const box = r.target_box && { min: vec3(r.target_box.min), max: vec3(r.target_box.max) };
    return {
      actionCost,
      kind: {
        case: "reach",
        value: {
          endEffector: r.end_effector,
          point: vec3(r.point),
          target: vec3(r.target),
          targetBox: box,
          successRadius: r.success_radius ?? 0,
          terminateOnSuccess: r.terminate_on_success ?? false,
        },
      },
    };
  }
  if (t.track) {
    const value = {
      targets: t.track.targets,
      tolerance: t.track.tolerance ?? 0,
      terminateOnSuccess: t.track.terminate_on_success ?? false,
    };
    return { actionCost, kind: { case: "track", value } };
  }
  if (t.upright) {
    const u = t.upright;
    const value = { instance: u.instance, axis: vec3(u.axis), maxTiltDeg: u.max_tilt_deg };
    return { actionCost, kind: { case: "upright", value } };
  }
  return { actionCost, kind: { case: "terms", value: { json: JSON.stringify(t.terms) } } };
}

/** The `EnvOptions` of CreateEnvRequest and CreateBatchRequest (their `options`), from
 * the guide's options. */
export function createFields(p: CreateEnvParams) {
  let documentJson = "";
  if (p.document !== undefined && p.model !== undefined) {
    throw invalid("give document or model, not both");
  }
  if (p.document === undefined && p.model === undefined) {
    throw invalid(
      "document is required: the assembly document (JSON, MJCF or URDF), or give model: a name from listModels",
    );
  }
  if (typeof p.document === "string") {
    documentJson = p.document;
  } else if (p.document !== undefined) {
    if (p.document === null || typeof p.document !== "object" || Array.isArray(p.document)) {
      throw invalid(
        'document must be the assembly document as a JSON object (with "parts" and "assembly"), ' +
          `or a string containing that JSON; got ${describe(p.document)}`,
      );
    }
    documentJson = JSON.stringify(p.document);
  }
  const gains = p.pd_gains && { kp: p.pd_gains.kp ?? [], kd: p.pd_gains.kd ?? [] };
  const range = (r: RangeJson | undefined) => r && { min: r.min, max: r.max };
  const randomize = p.randomize && {
    massScale: range(p.randomize.mass_scale),
    frictionScale: range(p.randomize.friction_scale),
    dampingScale: range(p.randomize.damping_scale),
    gainScale: range(p.randomize.gain_scale),
  };
  return {
    documentJson,
    model: p.model ?? "",
    assets: p.assets_base64 === undefined ? undefined : base64(p.assets_base64, "assets_base64", "base64"),
    endEffectorIds: p.end_effector_ids ?? [],
    dt: p.dt ?? 0,
    substeps: p.substeps ?? 0,
    maxSteps: p.max_steps ?? 0,
    seed: seed(p.seed),
    pdGains: gains,
    resetNoise: p.reset_noise,
    task: p.task && task(p.task),
    randomize,
  };
}
