/**
 * The tests' server: the `gymfleet-server` binary CI builds (`cargo test --workspace`),
 * as its own process on 127.0.0.1:0, found through the address its JSON log reports.
 * `GYMFLEET_SERVER_BIN` overrides the path (default: the workspace's debug build).
 */

import { spawn, type ChildProcess } from "node:child_process";
import { existsSync, readFileSync } from "node:fs";
import { resolve } from "node:path";
import { createInterface } from "node:readline";
import { fileURLToPath } from "node:url";

/** client/js (tests run from dist/test/). */
const packageRoot = fileURLToPath(new URL("../../", import.meta.url));

/** The seed models, by name: `models/<name>.json` of the workspace. */
export function model(name: string): { [key: string]: unknown } {
  return JSON.parse(readFileSync(resolve(packageRoot, "../../models", `${name}.json`), "utf8"));
}

/** A running server. */
export interface TestServer {
  /** `127.0.0.1:<port>`. */
  address: string;
  /** Stops it (SIGTERM: in-flight calls drain) and waits for it to exit. */
  stop(): Promise<void>;
}

function binary(): string {
  const path = resolve(
    process.cwd(),
    process.env.GYMFLEET_SERVER_BIN ?? resolve(packageRoot, "../../target/debug/gymfleet-server"),
  );
  if (!existsSync(path)) {
    throw new Error(
      `${path} not found: build it with \`cargo build -p gymfleet-server\` (or set GYMFLEET_SERVER_BIN)`,
    );
  }
  return path;
}

/** Starts a server with `flags` beside `--listen 127.0.0.1:0 --threads 2`. */
export async function startServer(flags: string[] = []): Promise<TestServer> {
  const args = ["--listen", "127.0.0.1:0", "--threads", "2", "--log-format", "json", ...flags];
  const child = spawn(binary(), args, { stdio: ["ignore", "ignore", "pipe"] });
  const log: string[] = [];
  const address = await new Promise<string>((found, failed) => {
    const timer = setTimeout(
      () => failed(new Error(`gymfleet-server did not start in 30 s:\n${log.join("\n")}`)),
      30_000,
    );
    child.on("error", failed);
    child.on("exit", (code) => failed(new Error(`gymfleet-server exited (${code}):\n${log.join("\n")}`)));
    createInterface({ input: child.stderr! }).on("line", (line) => {
      log.push(line);
      let fields: { message?: string; addr?: string } | undefined;
      try {
        fields = JSON.parse(line).fields;
      } catch {
        return; // not a log record (e.g. a flag error)
      }
      if (fields?.message === "serving gymfleet.v1.Simulator" && fields.addr) {
        clearTimeout(timer);
        found(fields.addr);
      }
    });
  });
  return { address, stop: () => stop(child) };
}

function stop(child: ChildProcess): Promise<void> {
  if (child.exitCode !== null) {
    return Promise.resolve();
  }
  const exited = new Promise<void>((done) => child.once("exit", () => done()));
  child.kill("SIGTERM");
  return exited;
}
