// `npm run check-breaking`: the gymfleet.v1 wire in ../../proto against the last release's,
// ../../proto/released.json (a buf image; `npm run release-proto` writes it at a release),
// under proto/buf.yaml's FILE rules: a field, message, enum value or RPC removed, renumbered,
// renamed or retyped fails; additions pass. Then it shows that the check can fail: a copy of
// proto/ with one field of StepRequest removed, and one with a field renumbered, must each
// be refused.

import { execFileSync } from "node:child_process";
import { cpSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { fileURLToPath } from "node:url";

const root = fileURLToPath(new URL("..", import.meta.url));
const buf = join(root, "node_modules", ".bin", "buf");
const proto = join(root, "..", "..", "proto");
const released = join(proto, "released.json");
const file = join("gymfleet", "v1", "simulator.proto");

/** buf breaking of the module at `dir` against the released image: [passed, output]. */
function breaking(dir) {
  try {
    execFileSync(buf, ["breaking", dir, "--against", released], { encoding: "utf8", stdio: "pipe" });
    return [true, ""];
  } catch (err) {
    return [false, `${err.stdout ?? ""}${err.stderr ?? ""}`];
  }
}

/** A copy of proto/ with `edit` applied to simulator.proto; whether buf refuses it. */
function refuses(what, edit, expected) {
  const dir = mkdtempSync(join(tmpdir(), "gymfleet-breaking-"));
  try {
    cpSync(proto, dir, { recursive: true });
    const path = join(dir, file);
    const before = readFileSync(path, "utf8");
    const after = edit(before);
    if (after === before) throw new Error(`the self-test's edit (${what}) changed nothing`);
    writeFileSync(path, after);
    const [passed, output] = breaking(dir);
    if (passed || !output.includes(expected)) {
      console.error(`the breaking-change check did not refuse ${what} with "${expected}":\n${output}`);
      process.exitCode = 1;
    } else {
      console.log(`refused, as it must be: ${what}`);
    }
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
}

const [passed, output] = breaking(proto);
if (!passed) {
  console.error(output);
  console.error(
    "proto/ breaks the released gymfleet.v1 wire: add fields and messages instead (mark old ones deprecated)",
  );
  process.exitCode = 1;
} else {
  console.log("proto/ keeps the released gymfleet.v1 wire (buf breaking, FILE rules)");
}
const stepRequest = /(message StepRequest \{[^}]*?)\n\s*repeated float values = 3;/;
refuses(
  "StepRequest.values removed",
  (text) => text.replace(stepRequest, "$1"),
  'Previously present field "3"',
);
refuses(
  "StepRequest.values renumbered",
  (text) => text.replace(/(message StepRequest \{[^}]*?repeated float values = )3;/, "$199;"),
  'Previously present field "3"',
);
