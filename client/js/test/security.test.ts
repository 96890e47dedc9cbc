/**
 * Tokens and TLS, as the other clients do them: `token` or GYMFLEET_TOKEN sent as
 * `authorization: Bearer <token>`; TLS with a CA (`tls.caFile`/`tls.ca` or
 * GYMFLEET_TLS_CA) and the certificate's name (`tls.domain`, GYMFLEET_TLS_DOMAIN); mutual
 * TLS with a client certificate (`tls.certFile`/`keyFile`, GYMFLEET_TLS_CLIENT_CERT and
 * _KEY). The test PKI is made with the openssl command line, in a temporary folder.
 */

import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { after, before, test } from "node:test";

import {
  Code,
  connect,
  createRobotEnv,
  gymObserve,
  gymReset,
  NotFound,
  Unauthenticated,
  Unavailable,
  type ConnectOptions,
} from "../src/index.js";
import { model, startServer, type TestServer } from "./server.js";

const TOKEN_A = "js-token-a-0123456789abcdef";
const TOKEN_B = "js-token-b-0123456789abcdef";

let dir: string;
const pki = (name: string) => join(dir, name);

/** A CA, and a server (localhost, 127.0.0.1) and a client certificate it signed. */
function makePki(): void {
  const openssl = (...args: string[]) => execFileSync("openssl", args, { cwd: dir, stdio: "pipe" });
  const key = ["-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes"];
  openssl(
    "req",
    "-x509",
    ...key,
    "-keyout",
    "ca.key",
    "-out",
    "ca.pem",
    "-days",
    "2",
    "-subj",
    "/CN=gymfleet test CA",
  );
  for (const [name, ext] of [
    ["server", "subjectAltName=DNS:localhost,IP:127.0.0.1\nextendedKeyUsage=serverAuth\n"],
    ["client", "extendedKeyUsage=clientAuth\n"],
  ] as const) {
    writeFileSync(pki(`${name}.ext`), ext);
    openssl("req", ...key, "-keyout", `${name}.key`, "-out", `${name}.csr`, "-subj", `/CN=${name}`);
    openssl(
      "x509",
      "-req",
      "-in",
      `${name}.csr`,
      "-CA",
      "ca.pem",
      "-CAkey",
      "ca.key",
      "-CAcreateserial",
      "-out",
      `${name}.pem`,
      "-days",
      "2",
      "-extfile",
      `${name}.ext`,
    );
  }
}

let auth: TestServer;
let tls: TestServer;
let mtls: TestServer;

before(async () => {
  dir = mkdtempSync(join(tmpdir(), "gymfleet-js-"));
  makePki();
  writeFileSync(pki("tokens"), `# tenant token\nteam-a ${TOKEN_A}\nteam-b ${TOKEN_B}\n`);
  const tlsFlags = ["--tls-cert", pki("server.pem"), "--tls-key", pki("server.key")];
  [auth, tls, mtls] = await Promise.all([
    startServer(["--auth-tokens", pki("tokens")]),
    startServer(tlsFlags),
    startServer([...tlsFlags, "--tls-client-ca", pki("ca.pem")]),
  ]);
});

after(async () => {
  await Promise.all([auth, tls, mtls].map((s) => s?.stop()));
  rmSync(dir, { recursive: true, force: true });
});

/** Runs `call` with these GYMFLEET_* variables set, then unsets them. */
async function withEnv<T>(vars: Record<string, string>, call: () => Promise<T>): Promise<T> {
  Object.assign(process.env, vars);
  try {
    return await call();
  } finally {
    for (const name of Object.keys(vars)) delete process.env[name];
  }
}

async function serverInfo(options: ConnectOptions) {
  const client = connect(options);
  try {
    return await client.simulator.getServerInfo({});
  } finally {
    client.close();
  }
}

function rejectsWith(Class: typeof Unauthenticated, code: Code, message: RegExp) {
  return (err: unknown) => {
    assert.ok(err instanceof Class, `${String(err)} is not ${Class.name}`);
    assert.equal(err.code, code);
    assert.match(err.message, message);
    if (code === Code.Unauthenticated) assert.equal(err.reason, "UNAUTHENTICATED");
    return true;
  };
}

test("a server that requires a token refuses none and a wrong one as UNAUTHENTICATED", async () => {
  await assert.rejects(
    serverInfo({ address: auth.address }),
    rejectsWith(
      Unauthenticated,
      Code.Unauthenticated,
      /^this server requires a token: send `authorization: Bearer <token>`/,
    ),
  );
  await assert.rejects(
    serverInfo({ address: auth.address, token: "not-a-known-token" }),
    rejectsWith(Unauthenticated, Code.Unauthenticated, /^authorization: unknown token$/),
  );
  const info = await serverInfo({ address: auth.address, token: TOKEN_A });
  assert.deepEqual([info.tenant, info.authRequired], ["team-a", true]);
});

test("the token comes from GYMFLEET_TOKEN, and a tenant's ids are unknown to another", async () => {
  const a = await withEnv({ GYMFLEET_TOKEN: TOKEN_A }, async () => connect({ address: auth.address }));
  const b = connect({ address: auth.address, token: TOKEN_B });
  const env = await createRobotEnv({ document: model("pendulum") }, a);
  assert.deepEqual((await gymReset(env, a)).joint_positions, [0]);
  await assert.rejects(
    gymObserve(env, b),
    rejectsWith(NotFound, Code.NotFound, new RegExp(`"${env.env_id}" not found`)),
  );
  assert.equal((await b.simulator.getServerInfo({})).envs, 0n);
  a.close();
  b.close();
});

test("TLS: trusting the server's CA, by file, text or GYMFLEET_TLS_CA", async () => {
  const domain = "localhost";
  const byFile = await serverInfo({ address: tls.address, tls: { caFile: pki("ca.pem"), domain } });
  assert.equal(byFile.threads, 2);
  const byText = await serverInfo({
    address: `https://${tls.address}`,
    tls: { ca: readFileSync(pki("ca.pem"), "utf8") },
  });
  assert.equal(byText.instanceId, byFile.instanceId);
  const byEnv = await withEnv({ GYMFLEET_TLS_CA: pki("ca.pem"), GYMFLEET_TLS_DOMAIN: domain }, () =>
    serverInfo({ address: tls.address }),
  );
  assert.equal(byEnv.instanceId, byFile.instanceId);
});

test("TLS failures are UNAVAILABLE: an untrusted certificate, plain text to TLS, TLS to plain text", async () => {
  await assert.rejects(
    serverInfo({ address: `https://${tls.address}` }),
    rejectsWith(Unavailable, Code.Unavailable, /certificate/),
  );
  // The server drops a plain-text HTTP/2 stream: CANCELLED, which is Unavailable's too.
  await assert.rejects(
    serverInfo({ address: tls.address }),
    rejectsWith(Unavailable, Code.Canceled, /^http\/2 stream closed with error code CANCEL \(0x8\)$/),
  );
  await assert.rejects(
    serverInfo({ address: `https://${auth.address}` }),
    rejectsWith(Unavailable, Code.Unavailable, /wrong version number/),
  );
});

test("mutual TLS admits a client with a certificate from its CA only", async () => {
  const ca = { caFile: pki("ca.pem"), domain: "localhost" };
  const info = await serverInfo({
    address: mtls.address,
    tls: { ...ca, certFile: pki("client.pem"), keyFile: pki("client.key") },
  });
  assert.equal(info.threads, 2);
  const byEnv = await withEnv(
    {
      GYMFLEET_TLS_CA: pki("ca.pem"),
      GYMFLEET_TLS_DOMAIN: "localhost",
      GYMFLEET_TLS_CLIENT_CERT: pki("client.pem"),
      GYMFLEET_TLS_CLIENT_KEY: pki("client.key"),
    },
    () => serverInfo({ address: mtls.address }),
  );
  assert.equal(byEnv.instanceId, info.instanceId);
  await assert.rejects(
    serverInfo({ address: mtls.address, tls: ca }),
    rejectsWith(Unavailable, Code.Unavailable, /alert certificate required/),
  );
});
