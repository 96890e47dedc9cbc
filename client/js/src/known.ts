/**
 * What a client remembers of the envs and batches it created: a terms task's names (to
 * name a step's terms) and a batch's shape and observation layout (to check actions and
 * to cut packed rows into the guide's per-env JSON). The server holds everything else.
 */

import type { GymfleetClient } from "./client.js";
import type { BatchInfo } from "./gen/gymfleet/v1/simulator_pb.js";

/** One client's record. */
export interface Known {
  /** env_id → its terms task's term names (empty without one). */
  envs: Map<string, string[]>;
  /** batch_id → its BatchInfo. */
  batches: Map<string, BatchInfo>;
}

const records = new WeakMap<GymfleetClient, Known>();

/** `client`'s record, made on first use. */
export function known(client: GymfleetClient): Known {
  let record = records.get(client);
  if (record === undefined) {
    record = { envs: new Map(), batches: new Map() };
    records.set(client, record);
  }
  return record;
}
