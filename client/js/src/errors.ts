/**
 * The errors of gymfleet: one class per status class the server answers with, all under
 * {@link GymfleetError}, the same classes as the Python package's (`gymfleet.errors`) and
 * the same classification as the Rust client's `ClientError`.
 *
 * Every error's `message` is the server's message, which names the offending field (with
 * its JSON path for documents), id or limit; `code` is the gRPC status code it came with
 * (a {@link Code}, e.g. `Code.NotFound` = 5). Arguments this client refuses before
 * calling (an unknown action type, a non-finite action value) are {@link InvalidArgument}
 * with `Code.InvalidArgument`, as the server would answer.
 */

import { Code, ConnectError } from "@connectrpc/connect";

export { Code };

/** Base class of every error a gymfleet call throws. */
export class GymfleetError extends Error {
  /** The gRPC status code. */
  readonly code: Code;
  /** Why, for programs: the server's `ErrorReason` as it travels (the proto's name
   * without `ERROR_REASON_`, e.g. `"ENV_NOT_FOUND"`), from the status's
   * `gymfleet-reason` metadata; `"INVALID_ACTION"` for this client's own action checks;
   * `undefined` for what the client found itself (a connection, a deadline) or a server
   * that sent none. */
  readonly reason: string | undefined;
  /** The server flag that raises the limit a {@link ResourceExhausted} was for (the
   * status's `gymfleet-limit` metadata), e.g. `"--max-envs"`. */
  readonly limit: string | undefined;

  constructor(
    message: string,
    code: Code,
    options?: { cause?: unknown; reason?: string | undefined; limit?: string | undefined },
  ) {
    super(message, options);
    this.code = code;
    this.reason = options?.reason;
    this.limit = options?.limit;
    this.name = new.target.name;
  }
}

/** INVALID_ARGUMENT (or OUT_OF_RANGE for a value): a bad document, option or action;
 * nothing was created or stepped. */
export class InvalidArgument extends GymfleetError {}

/** NOT_FOUND: the env or batch id is unknown on the server: closed, reclaimed after
 * idling, another tenant's, or the server restarted. */
export class NotFound extends GymfleetError {}

/** RESOURCE_EXHAUSTED: a server limit (envs, batch size, message size) was hit; the
 * message names the limit and how to raise it. */
export class ResourceExhausted extends GymfleetError {}

/** FAILED_PRECONDITION: the call is not possible in the env's state, e.g. stepping an env
 * whose physics diverged before resetting it. */
export class FailedPrecondition extends GymfleetError {}

/** UNAUTHENTICATED: the server requires a token (`--auth-tokens`) and got none, or a bad
 * one: pass `token` to `connect`, or set `GYMFLEET_TOKEN`. */
export class Unauthenticated extends GymfleetError {}

/** DEADLINE_EXCEEDED: no reply within the call's deadline (`timeoutMs`). Whether the
 * server did the work is unknown (a batch may have stepped some envs): reset before going
 * on. */
export class DeadlineExceeded extends GymfleetError {}

/** UNAVAILABLE, CANCELLED or ABORTED: the server cannot be reached (refused, TLS
 * handshake failed), is shutting down, or the call was cut short. Retrying may help. */
export class Unavailable extends GymfleetError {}

/** INTERNAL, UNKNOWN or DATA_LOSS: a server bug; also a status this client does not
 * expect from a gymfleet server (ALREADY_EXISTS, PERMISSION_DENIED, UNIMPLEMENTED). */
export class Internal extends GymfleetError {}

/** The class for each gRPC status code, as the Rust client classifies them. */
function classOf(code: Code): typeof GymfleetError {
  switch (code) {
    case Code.InvalidArgument:
      return InvalidArgument;
    case Code.NotFound:
      return NotFound;
    // tonic reports an over-size message as OUT_OF_RANGE.
    case Code.ResourceExhausted:
    case Code.OutOfRange:
      return ResourceExhausted;
    case Code.FailedPrecondition:
      return FailedPrecondition;
    case Code.Unauthenticated:
      return Unauthenticated;
    case Code.DeadlineExceeded:
      return DeadlineExceeded;
    case Code.Unavailable:
    case Code.Canceled:
    case Code.Aborted:
      return Unavailable;
    case Code.Internal:
    case Code.Unknown:
    case Code.DataLoss:
    case Code.AlreadyExists:
    case Code.PermissionDenied:
    case Code.Unimplemented:
      return Internal;
  }
}

/** How a program using this client points it at another server, as connection errors
 * say it. */
export const POINT_THE_CLIENT = "pass its address as `address` to connect (or set GYMFLEET_SERVER)";

/** What every gymfleet client (Rust, Python, TypeScript, the load client, the MCP adapter)
 * says when it cannot connect to a server: the address, the cause, "Is the server
 * running?", and `how` to point the program at another server. */
export function cannotConnect(address: string, reason: string, how: string = POINT_THE_CLIENT): string {
  const cause = reason.replace(/\.+$/, "");
  return `cannot connect to the gymfleet server at ${address}: ${cause}. Is the server running? To use another one, ${how}.`;
}

/** Whether `err` is a failure of the connection rather than the server's answer (which
 * has no cause): a Node error with a code (refused, unreachable, a TLS handshake or
 * certificate failure, a peer that does not speak TLS) somewhere in its causes. */
function isConnectFailure(err: ConnectError): boolean {
  const seen = new Set<unknown>();
  for (let cause = err.cause; cause instanceof Error && !seen.has(cause); cause = cause.cause) {
    if (typeof (cause as { code?: unknown }).code === "string") {
      return true;
    }
    seen.add(cause);
  }
  return false;
}

/** `reason` (what a Connect call threw) as a {@link GymfleetError}; one already is stays
 * as it is. The original error is kept as `cause`. A failed connection (which Connect
 * reports as UNAVAILABLE, or INTERNAL for TLS) is {@link Unavailable}, and with the
 * server's `address` its message is {@link cannotConnect}'s. */
export function toGymfleetError(reason: unknown, address?: string): GymfleetError {
  if (reason instanceof GymfleetError) {
    return reason;
  }
  const err = ConnectError.from(reason);
  const failed = isConnectFailure(err) && (err.code === Code.Internal || err.code === Code.Unavailable);
  const code = failed ? Code.Unavailable : err.code;
  const Class = classOf(code);
  const message = failed && address !== undefined ? cannotConnect(address, err.rawMessage) : err.rawMessage;
  return new Class(message, code, {
    cause: reason,
    reason: err.metadata.get(REASON_KEY) ?? undefined,
    limit: err.metadata.get(LIMIT_KEY) ?? undefined,
  });
}

/** The status metadata entries that carry an error's reason and a refusing limit's flag
 * (the proto's `ErrorReason`). */
export const REASON_KEY = "gymfleet-reason";
export const LIMIT_KEY = "gymfleet-limit";

/** An {@link InvalidArgument} found by this client before any call; `reason` when it
 * stands in for the server's check of the same kind (an action's). */
export function invalid(message: string, reason?: string): InvalidArgument {
  return new InvalidArgument(message, Code.InvalidArgument, { reason });
}
