// The dashboard in a real browser: Debian's headless Chromium (software WebGL), driven by
// playwright-core, against the server of `tests/examples/dashboard_fixture.rs` (auth on;
// tenant team-a holds a batch of pendulums whose arm is named <script>alert(1)</script>,
// tenant team-b a batch of arms). Checks that
//   - with team-a's token the page loads with no console errors, keeps a session cookie
//     that is HttpOnly and SameSite=Strict (and never the token in a URL), lists team-a's
//     batch and not team-b's, and shows the hostile name as text with no dialog;
//   - its 3D view changes where the env steps (the fixture steps it on request), and it
//     lists the selected batch's keyframes and sensors;
//   - a wrong token sees nothing: the login refuses it, the lists stay empty, the API
//     answers 401.
// Usage: node dashboard.test.mjs [FIXTURE] (default: ../../target/debug/examples/dashboard_fixture,
// which `cargo test` builds)

import { chromium } from 'playwright-core';
import { check } from './check.mjs';
import { spawn } from 'node:child_process';
import { existsSync } from 'node:fs';
import { createInterface } from 'node:readline';
import { fileURLToPath } from 'node:url';
import path from 'node:path';

const here = path.dirname(fileURLToPath(import.meta.url));
const fixture_path = path.resolve(process.argv[2] ?? path.join(here, '../../target/debug/examples/dashboard_fixture'));
if (!existsSync(fixture_path)) {
  console.error(`no fixture at ${fixture_path}: build it first (cargo build -p gymfleet-e2e --example dashboard_fixture)`);
  process.exit(1);
}
const executablePath = process.env.CHROMIUM ?? '/usr/bin/chromium';
const HOSTILE = '<script>alert(1)</script>';

// The fixture: its first line describes the server; later lines answer `step N`.
const fixture = spawn(fixture_path, [], { stdio: ['pipe', 'pipe', 'inherit'] });
const lines = createInterface({ input: fixture.stdout });
const waiting = [];
lines.on('line', (line) => waiting.shift()?.(line));
const nextLine = () => new Promise((resolve, reject) => {
  const timer = setTimeout(() => reject(new Error('the fixture did not answer within 60 s')), 60000);
  waiting.push((line) => { clearTimeout(timer); resolve(line); });
});
const step = async (n) => {
  const answer = nextLine();
  fixture.stdin.write(`step ${n}\n`);
  return answer;
};

const browser_args = [
  '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--disable-quic', '--no-first-run', '--disable-background-networking',
  '--disable-component-update', '--disable-sync',
];

let browser;
try {
  const server = JSON.parse(await nextLine());
  browser = await chromium.launch({ executablePath, headless: true, args: browser_args });

  // --- team-a, with its token -------------------------------------------------------
  const context = await browser.newContext({ viewport: { width: 1200, height: 900 } });
  const page = await context.newPage();
  const errors = [], dialogs = [], urls = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('requestfailed', (r) => errors.push(`request failed: ${r.url().slice(0, 80)}`));
  page.on('dialog', (d) => { dialogs.push(d.message()); d.dismiss(); });
  page.on('request', (r) => urls.push(r.url()));
  await page.goto(server.url);
  await page.waitForSelector('#login:not([hidden])', { timeout: 30000 });
  check(true, 'the page asks for a token');
  await page.fill('#token', server.token);
  await page.click('#login-form button[type=submit]');
  await page.waitForFunction(() => window.dashboard?.frames >= 2, null, { timeout: 30000 });

  const cookies = await context.cookies();
  const session = cookies.find((c) => c.name === 'gymfleet_dashboard');
  check(session && session.httpOnly && session.sameSite === 'Strict',
    `the session cookie is HttpOnly and SameSite=Strict (${JSON.stringify(session && { httpOnly: session.httpOnly, sameSite: session.sameSite })})`);
  check(!session.value.includes(server.token), 'the cookie is a session id, not the token');
  check(await page.evaluate(() => document.cookie) === '', 'scripts cannot read the cookie');
  check(urls.every((u) => !u.includes(server.token)), `the token is in no URL (${urls.length} requests)`);
  check(urls.every((u) => u.startsWith(server.url)), 'nothing is fetched from elsewhere');

  const listed = await page.$$eval('#batches tbody tr', (rows) => rows.map((r) => r.dataset.id));
  check(listed.includes(server.batch), `the batch ${server.batch} is listed (${listed})`);
  check(!listed.includes(server.other_batch), `the other tenant's ${server.other_batch} is not`);
  check(await page.textContent('#who') === 'tenant team-a', 'the page names the tenant');

  const names = await page.$$eval('#bodies li', (items) => items.map((li) => li.textContent));
  check(names.includes(HOSTILE), `the instance named ${HOSTILE} shows as text (${JSON.stringify(names)})`);
  check(await page.evaluate(() => document.scripts.length) === 1, 'no script element was injected');

  // The 3D view: the canvas's pixels before and after the env steps.
  const shot = () => page.evaluate(() => {
    const src = window.dashboard.canvas;
    const c = document.createElement('canvas');
    c.width = src.width; c.height = src.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(src, 0, 0);
    return { w: c.width, h: c.height, px: Array.from(ctx.getImageData(0, 0, c.width, c.height).data) };
  });
  const before = await shot();
  const colours = new Set();
  for (let k = 0; k < before.px.length; k += 4 * 7) colours.add(before.px.slice(k, k + 3).join(','));
  check(before.w > 300 && before.h > 300, `the canvas has a size (${before.w}x${before.h})`);
  check(colours.size > 20, `the canvas is not blank (${colours.size} colours sampled)`);
  const answer = await step(60);
  check(answer.startsWith('stepped'), `the fixture stepped the batch (${answer})`);
  const frames = await page.evaluate(() => window.dashboard.frames);
  await page.waitForFunction((f) => window.dashboard.frames >= f + 2, frames, { timeout: 30000 });
  const after = await shot();
  let changed = 0;
  for (let k = 0; k < before.px.length; k += 4) {
    const d = Math.abs(before.px[k] - after.px[k]) + Math.abs(before.px[k + 1] - after.px[k + 1]) + Math.abs(before.px[k + 2] - after.px[k + 2]);
    if (d > 24) changed++;
  }
  check(changed > 200, `the view changed as the env stepped (${changed} pixels)`);
  // 60 steps of 4 envs: the list counts them at its next refresh.
  const cell = `#batches tbody tr[data-id="${server.batch}"] td:nth-child(3)`;
  await page.waitForFunction((cell) => document.querySelector(cell)?.textContent === '240', cell, { timeout: 30000 });
  check(true, "the batch's 240 env steps are counted");
  const details = await page.evaluate(() => document.getElementById('view-details').textContent);
  check(details === 'keyframes: raised · sensors: angle (jointpos)', `the view lists the keyframes and sensors (${details})`);
  check(dialogs.length === 0, `no dialog opened${dialogs.length ? ': ' + dialogs.join(' | ') : ''}`);
  check(errors.length === 0, `no console or page errors${errors.length ? ': ' + errors.join(' | ') : ''}`);

  // --- a wrong token ------------------------------------------------------------------
  const stranger = await browser.newContext({ viewport: { width: 1200, height: 900 } });
  const other = await stranger.newPage();
  const other_errors = [];
  other.on('pageerror', (e) => other_errors.push(String(e)));
  other.on('dialog', (d) => { dialogs.push(d.message()); d.dismiss(); });
  await other.goto(server.url);
  await other.waitForSelector('#login:not([hidden])', { timeout: 30000 });
  await other.fill('#token', 'team-a-browser-XXXXXXXXXX');
  await other.click('#login-form button[type=submit]');
  await other.waitForFunction(() => document.getElementById('login-error').textContent !== '', null, { timeout: 30000 });
  check(await other.textContent('#login-error') === 'unknown token', 'a wrong token is refused');
  check(await other.isHidden('#main'), 'and sees no lists');
  check(await other.$$eval('#batches tbody tr, #envs tbody tr', (rows) => rows.length) === 0, 'the lists are empty');
  check((await stranger.cookies()).length === 0, 'and gets no cookie');
  const api = await other.evaluate(async (batch) => {
    const overview = await fetch('/api/overview');
    const scene = await fetch(`/api/batches/${batch}/envs/0/scene`);
    return [overview.status, scene.status, (await overview.json()).batches];
  }, server.batch);
  check(api[0] === 401 && api[1] === 401 && api[2] === undefined, `the API answers 401 and lists nothing (${api})`);
  check(other_errors.length === 0, `no page errors${other_errors.length ? ': ' + other_errors.join(' | ') : ''}`);
  check(dialogs.length === 0, 'still no dialog');
} finally {
  await browser?.close();
  fixture.stdin.end();
  await new Promise((resolve) => {
    if (fixture.exitCode !== null) resolve();
    else fixture.on('exit', resolve);
  });
}
