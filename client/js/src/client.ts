/**
 * {@link connect}: one connection to a gymfleet server, as a {@link GymfleetClient}
 * whose `simulator` is Connect's typed client of `gymfleet.v1.Simulator` (every RPC,
 * with the generated request and reply types), speaking plain gRPC over HTTP/2.
 *
 * Settings not given come from the variables every gymfleet client and tool reads:
 * `GYMFLEET_SERVER` (the address; default `127.0.0.1:50051`), `GYMFLEET_TOKEN` (bearer
 * token), `GYMFLEET_TLS_CA` (connect with TLS, trusting this CA file),
 * `GYMFLEET_TLS_CLIENT_CERT` and `GYMFLEET_TLS_CLIENT_KEY` (mutual TLS) and
 * `GYMFLEET_TLS_DOMAIN` (the name on the server's certificate).
 */

import { readFileSync } from "node:fs";
import type { SecureClientSessionOptions } from "node:http2";

import { createClient, type Client, type Interceptor } from "@connectrpc/connect";
import { createGrpcTransport, Http2SessionManager } from "@connectrpc/connect-node";

import { invalid, toGymfleetError } from "./errors.js";
import { Simulator } from "./gen/gymfleet/v1/simulator_pb.js";

/** The address used when neither `address` nor `GYMFLEET_SERVER` gives one. */
export const DEFAULT_ADDRESS = "127.0.0.1:50051";
/** Largest message decoded or encoded by default: 64 MiB, like the server and the Rust
 * client. */
export const DEFAULT_MAX_MESSAGE_BYTES = 64 * 1024 * 1024;

/** TLS settings. PEM text (`ca`, `cert`, `key`) or files (`caFile`, `certFile`,
 * `keyFile`, read when connecting). */
export interface TlsOptions {
  /** Trust these CA certificates (PEM) instead of the system's. */
  ca?: string | Uint8Array;
  /** Trust the CA certificates of this PEM file instead of the system's. */
  caFile?: string;
  /** Mutual TLS: this client's certificate (PEM); needs `key` or `keyFile`. */
  cert?: string | Uint8Array;
  /** Mutual TLS: this client's certificate file (PEM). */
  certFile?: string;
  /** Mutual TLS: the private key (PEM) of the client certificate. */
  key?: string | Uint8Array;
  /** Mutual TLS: the private key file (PEM) of the client certificate. */
  keyFile?: string;
  /** The name the server's certificate must carry, when it is not the address's host
   * (e.g. connecting by IP address). */
  domain?: string;
}

/** How to reach a server. */
export interface ConnectOptions {
  /** `host:port`, `http://host:port` or `https://host:port` (TLS with the system's CAs).
   * Default: `GYMFLEET_SERVER`, else {@link DEFAULT_ADDRESS}. */
  address?: string;
  /** Bearer token sent as `authorization: Bearer <token>` with every call (servers run
   * with `--auth-tokens`). Default: `GYMFLEET_TOKEN`. */
  token?: string;
  /** Connect with TLS. Default: from the `GYMFLEET_TLS_*` variables; TLS is on when any
   * is set, or when the address is `https://`. */
  tls?: TlsOptions;
  /** Every call's deadline in milliseconds, sent as `grpc-timeout` (default: none). A
   * call without an answer by then throws {@link DeadlineExceeded}. */
  timeoutMs?: number;
  /** Largest message decoded or encoded (default {@link DEFAULT_MAX_MESSAGE_BYTES}). */
  maxMessageBytes?: number;
}

/** A connection to a gymfleet server. The HTTP/2 connection opens on the first call, is
 * kept alive with pings (every 5 s, dead after 10 s without an answer, like the Rust
 * client), and does not keep the process alive while idle. */
export class GymfleetClient {
  /** The address as given (or read from `GYMFLEET_SERVER`). */
  readonly address: string;
  /** The typed client of every RPC of `gymfleet.v1.Simulator` (protobuf-es messages,
   * camelCase fields). Its calls throw {@link GymfleetError} subclasses too. */
  readonly simulator: Client<typeof Simulator>;
  private readonly session: Http2SessionManager;

  /** Use {@link connect}. */
  constructor(address: string, simulator: Client<typeof Simulator>, session: Http2SessionManager) {
    this.address = address;
    this.simulator = simulator;
    this.session = session;
  }

  /** Closes the connection, ending calls in flight. A later call reconnects. */
  close(): void {
    this.session.abort();
  }
}

function env(name: string): string | undefined {
  const value = process.env[name];
  return value === undefined || value === "" ? undefined : value;
}

/** The TLS settings of the `GYMFLEET_TLS_*` variables, or `undefined` if none is set. */
function tlsFromEnvironment(): TlsOptions | undefined {
  const caFile = env("GYMFLEET_TLS_CA");
  const certFile = env("GYMFLEET_TLS_CLIENT_CERT");
  const keyFile = env("GYMFLEET_TLS_CLIENT_KEY");
  const domain = env("GYMFLEET_TLS_DOMAIN");
  if ((certFile === undefined) !== (keyFile === undefined)) {
    throw invalid("GYMFLEET_TLS_CLIENT_CERT and GYMFLEET_TLS_CLIENT_KEY go together: set both or neither");
  }
  if (caFile === undefined && certFile === undefined && domain === undefined) {
    return undefined;
  }
  return { caFile, certFile, keyFile, domain };
}

/** PEM text given directly, or read from a file now. */
function pem(text: string | Uint8Array | undefined, file: string | undefined, what: string) {
  if (text !== undefined) {
    return typeof text === "string" ? text : Buffer.from(text);
  }
  if (file === undefined) {
    return undefined;
  }
  try {
    return readFileSync(file);
  } catch (err) {
    throw invalid(`${what} ${file}: ${(err as Error).message}`);
  }
}

/** Node's TLS options for `tls`. */
function secureOptions(tls: TlsOptions): SecureClientSessionOptions {
  if (((tls.cert ?? tls.certFile) === undefined) !== ((tls.key ?? tls.keyFile) === undefined)) {
    throw invalid("tls: a client certificate and its key go together: give both or neither");
  }
  const cert = pem(tls.cert, tls.certFile, "TLS client certificate");
  const key = pem(tls.key, tls.keyFile, "TLS client key");
  const options: SecureClientSessionOptions = {};
  const ca = pem(tls.ca, tls.caFile, "TLS CA file");
  if (ca !== undefined) options.ca = ca;
  if (cert !== undefined) options.cert = cert;
  if (key !== undefined) options.key = key;
  if (tls.domain !== undefined) options.servername = tls.domain;
  return options;
}

/** The URL of `address`; `https` when TLS settings are given. */
function baseUrl(address: string, tls: boolean): URL {
  const withScheme = /^https?:\/\//i.test(address);
  let url: URL | undefined;
  if (withScheme || /^[^\s/,]+:\d+$/.test(address)) {
    try {
      url = new URL(withScheme ? address : `http://${address}`);
    } catch {
      url = undefined;
    }
  }
  if (url === undefined) {
    throw invalid(
      `address ${JSON.stringify(address)}: expected host:port, http://host:port or https://host:port`,
    );
  }
  if (tls) {
    url.protocol = "https:";
  }
  return url;
}

/** Adds the bearer token to every call. */
function bearer(token: string): Interceptor {
  if (!/^[\x21-\x7e]+$/.test(token)) {
    throw invalid("token: expected a non-empty bearer token of printable ASCII without spaces");
  }
  const value = `Bearer ${token}`;
  return (next) => async (req) => {
    req.header.set("authorization", value);
    return next(req);
  };
}

type Call = (...args: unknown[]) => unknown;

async function* classifyStream(messages: AsyncIterable<unknown>, address: string) {
  try {
    yield* messages;
  } catch (err) {
    throw toGymfleetError(err, address);
  }
}

/** `client` with every failure of a call, a streamed reply's included, thrown as a
 * GymfleetError. (Connect wraps what an interceptor throws in a ConnectError, so the
 * methods themselves are wrapped.) */
function classifyErrors(client: Client<typeof Simulator>, address: string): Client<typeof Simulator> {
  const calls = client as unknown as Record<string, Call>;
  const wrapped: Record<string, Call> = {};
  for (const method of Simulator.methods) {
    const call = calls[method.localName]!;
    wrapped[method.localName] =
      method.methodKind === "unary"
        ? async (...args) => {
            try {
              return await call(...args);
            } catch (err) {
              throw toGymfleetError(err, address);
            }
          }
        : (...args) => classifyStream(call(...args) as AsyncIterable<unknown>, address);
  }
  return wrapped as unknown as Client<typeof Simulator>;
}

/** A client of the server at `options.address` (see {@link ConnectOptions}; unset
 * settings come from the `GYMFLEET_*` variables). Nothing is sent until the first call:
 * an unreachable server fails that call with {@link Unavailable}. */
export function connect(options: ConnectOptions = {}): GymfleetClient {
  const address = options.address ?? env("GYMFLEET_SERVER") ?? DEFAULT_ADDRESS;
  const token = options.token ?? env("GYMFLEET_TOKEN");
  const tls = options.tls ?? tlsFromEnvironment();
  const url = baseUrl(address, tls !== undefined);
  const nodeOptions = url.protocol === "https:" ? secureOptions(tls ?? {}) : {};
  const session = new Http2SessionManager(url, { pingIntervalMs: 5_000, pingTimeoutMs: 10_000 }, nodeOptions);
  const interceptors = token === undefined ? [] : [bearer(token)];
  const maxBytes = options.maxMessageBytes ?? DEFAULT_MAX_MESSAGE_BYTES;
  const transport = createGrpcTransport({
    baseUrl: url.toString(),
    sessionManager: session,
    interceptors,
    defaultTimeoutMs: options.timeoutMs,
    readMaxBytes: maxBytes,
    writeMaxBytes: maxBytes,
  });
  return new GymfleetClient(address, classifyErrors(createClient(Simulator, transport), address), session);
}

let defaultConnection: GymfleetClient | undefined;

/** The connection the gym functions use when they are given none: {@link connect} with
 * the `GYMFLEET_*` variables, made on first use. */
export function defaultClient(): GymfleetClient {
  defaultConnection ??= connect();
  return defaultConnection;
}
