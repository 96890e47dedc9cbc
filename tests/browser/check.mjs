// The browser tests' one assertion: prints `ok: …`, or `FAIL: …` and throws (setting a
// failing exit code), so a test stops at its first failed check.
export function check(ok, message) {
  if (!ok) {
    console.error(`FAIL: ${message}`);
    process.exitCode = 1;
    throw new Error(message);
  }
  console.log(`ok: ${message}`);
}
