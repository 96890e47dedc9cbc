/**
 * {@link batchStream}: a batch's steps pipelined over one `StreamBatch` stream, EnvPool's
 * asynchronous way: `send` a step (of every env, or of `env_indices`) and return at once,
 * with any number on the wire; `recv` the oldest send's result. Each listed env steps
 * exactly as in a whole-batch step, so the same seeds and actions per env give the same
 * per-env rows, bit for bit, however the envs are grouped.
 *
 * The server answers nothing on a stream after a failed step: `recv` throws that step's
 * error (with its `envIndices`), and the sends behind it, which the server did not step,
 * go out again on a new stream, so that each env steps exactly once.
 */

import { type GymfleetClient, defaultClient } from "./client.js";
import { GymfleetError, invalid } from "./errors.js";
import type { BatchStepResult, StepBatchRequest } from "./gen/gymfleet/v1/simulator_pb.js";
import { packedStep, type BatchIdJson, type PackedBatchStep } from "./batch.js";
import { actionType, pushActionValues, type ActionTypeName } from "./params.js";

/** A {@link GymfleetError} of a streamed step, with the envs it concerns. */
export type StepError = GymfleetError & { envIndices: number[] };

type Request = Pick<StepBatchRequest, "batchId" | "actionType" | "actions" | "envIndices">;

/** The request side of one stream: an async iterable that `push` feeds. */
class Requests implements AsyncIterable<Request> {
  private readonly items: Request[] = [];
  private waiting: ((r: IteratorResult<Request>) => void) | undefined;
  private ended = false;

  push(item: Request): void {
    const waiting = this.waiting;
    this.waiting = undefined;
    if (waiting !== undefined) waiting({ value: item, done: false });
    else this.items.push(item);
  }

  end(): void {
    this.ended = true;
    const waiting = this.waiting;
    this.waiting = undefined;
    if (waiting !== undefined) waiting({ value: undefined, done: true });
  }

  [Symbol.asyncIterator](): AsyncIterator<Request> {
    return {
      next: () => {
        const item = this.items.shift();
        if (item !== undefined) return Promise.resolve({ value: item, done: false });
        if (this.ended) return Promise.resolve({ value: undefined, done: true });
        return new Promise((resolve) => (this.waiting = resolve));
      },
      // The transport ends the request side this way when the call ends.
      return: () => {
        this.end();
        return Promise.resolve({ value: undefined, done: true });
      },
      throw: () => {
        this.end();
        return Promise.resolve({ value: undefined, done: true });
      },
    };
  }
}

interface Send {
  request: Request;
  /** On the current stream (false: to go out again on the next one). */
  sent: boolean;
}

/** One batch's pipelined steps; made by {@link batchStream}. */
export class BatchStream {
  private requests!: Requests;
  private responses!: AsyncIterator<BatchStepResult>;
  private accepting = false;
  private readonly pending: Send[] = [];

  constructor(
    private readonly client: GymfleetClient,
    readonly batchId: string,
  ) {
    this.open();
  }

  /** Sends one step and returns at once: `actions` holds one row of action_dim values per
   * env (every env, or each of `env_indices`, ascending and distinct, in that order). */
  send(params: { action_type: ActionTypeName; actions: ArrayLike<number>; env_indices?: number[] }): void {
    const values: number[] = [];
    pushActionValues(values, params.actions, "actions");
    const request = {
      batchId: this.batchId,
      actionType: actionType(params.action_type),
      actions: values,
      envIndices: params.env_indices ?? [],
    };
    const send = { request, sent: false };
    this.pending.push(send);
    this.put(send);
  }

  /** Sends whose results {@link BatchStream.recv} has not returned yet. */
  get inFlight(): number {
    return this.pending.length;
  }

  /** The oldest send's result. Throws its error (a {@link StepError}) if the server
   * refused it; the sends behind it go out again. */
  async recv(): Promise<PackedBatchStep> {
    const head = this.pending[0];
    if (head === undefined) throw invalid("recv: no step was sent on the stream (send one first)");
    if (!head.sent) {
      this.open();
      for (const send of this.pending) this.put(send);
    }
    let next: IteratorResult<BatchStepResult>;
    try {
      next = await this.responses.next();
    } catch (err) {
      this.pending.shift();
      // The server stepped nothing after it: those sends go out again when taken.
      this.accepting = false;
      this.requests.end();
      for (const send of this.pending) send.sent = false;
      if (err instanceof GymfleetError) {
        throw Object.assign(err, { envIndices: head.request.envIndices }) as StepError;
      }
      throw err;
    }
    if (next.done) throw invalid("recv: the server ended the stream before answering every step");
    this.pending.shift();
    return packedStep(next.value);
  }

  /** Ends the request side (the results already sent still come back with `recv`). */
  close(): void {
    this.accepting = false;
    this.requests.end();
  }

  private open(): void {
    this.requests = new Requests();
    this.responses = this.client.simulator.streamBatch(this.requests)[Symbol.asyncIterator]();
    this.accepting = true;
  }

  private put(send: Send): void {
    if (!this.accepting) return;
    this.requests.push(send.request);
    send.sent = true;
  }
}

/** A {@link BatchStream} of a batch of the server (any batch, as batchStepPacked). */
export function batchStream(params: BatchIdJson, client: GymfleetClient = defaultClient()): BatchStream {
  return new BatchStream(client, params.batch_id);
}
