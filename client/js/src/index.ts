/**
 * gymfleet for TypeScript and JavaScript (Node ≥ 20): the user guide's gym tools as
 * functions that take and return the guide's JSON (`createRobotEnv`, `gymStep`,
 * `batchStep`, …), packed batch calls with `Float32Array` observations, and, for every
 * RPC of `gymfleet.v1.Simulator`, Connect's typed client (`connect().simulator`) over the
 * types protoc-gen-es generates from `proto/` into `src/gen/`. Errors are
 * {@link GymfleetError} subclasses carrying the gRPC status code.
 *
 * The simulator runs in a gymfleet server: this package is a network client only.
 */

export {
  connect,
  defaultClient,
  DEFAULT_ADDRESS,
  DEFAULT_MAX_MESSAGE_BYTES,
  GymfleetClient,
  type ConnectOptions,
  type TlsOptions,
} from "./client.js";
export {
  Code,
  DeadlineExceeded,
  FailedPrecondition,
  GymfleetError,
  Internal,
  InvalidArgument,
  NotFound,
  ResourceExhausted,
  cannotConnect,
  LIMIT_KEY,
  POINT_THE_CLIENT,
  REASON_KEY,
  toGymfleetError,
  Unauthenticated,
  Unavailable,
} from "./errors.js";
export * from "./gym.js";
export * from "./batch.js";
export * from "./stream.js";
export type * from "./params.js";
export { clean, POSE_LEN } from "./shapes.js";
export type * from "./shapes.js";
export * from "./gen/gymfleet/v1/simulator_pb.js";
