// `npm run check-generated`: regenerates the protobuf-es code from ../../proto into a
// temporary folder, with buf.gen.yaml as `npm run generate` does, and fails when it
// differs from the committed src/gen/ (a proto change without `npm run generate`, or a
// hand edit of generated code).

import { execFileSync } from "node:child_process";
import { mkdtempSync, readdirSync, readFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { delimiter, join, relative } from "node:path";
import { fileURLToPath } from "node:url";

const root = fileURLToPath(new URL("..", import.meta.url));
const bin = join(root, "node_modules", ".bin");
const committed = join(root, "src", "gen");

/** Every file under `dir`, as paths relative to it. */
function files(dir) {
  return readdirSync(dir, { recursive: true, withFileTypes: true })
    .filter((entry) => entry.isFile())
    .map((entry) => relative(dir, join(entry.parentPath ?? entry.path, entry.name)))
    .sort();
}

const out = mkdtempSync(join(tmpdir(), "gymfleet-gen-"));
try {
  execFileSync(join(bin, "buf"), ["generate", "--output", out], {
    cwd: root,
    stdio: "inherit",
    env: { ...process.env, PATH: `${bin}${delimiter}${process.env.PATH}` },
  });
  const fresh = join(out, "src", "gen");
  const want = files(fresh);
  const have = files(committed);
  const drift = [
    ...want.filter((f) => !have.includes(f)).map((f) => `missing: src/gen/${f}`),
    ...have.filter((f) => !want.includes(f)).map((f) => `not generated from proto/: src/gen/${f}`),
    ...want
      .filter((f) => have.includes(f))
      .filter((f) => !readFileSync(join(fresh, f)).equals(readFileSync(join(committed, f))))
      .map((f) => `differs from what proto/ generates: src/gen/${f}`),
  ];
  if (drift.length > 0) {
    console.error(drift.join("\n"));
    console.error("src/gen is out of date: run `npm run generate` in client/js and commit the result");
    process.exitCode = 1;
  } else {
    console.log(`src/gen matches proto/ (${want.length} file${want.length === 1 ? "" : "s"})`);
  }
} finally {
  rmSync(out, { recursive: true, force: true });
}
