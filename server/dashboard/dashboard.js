// The gymfleet dashboard page: polls the server's JSON API (server/src/dashboard/) and
// shows the caller's envs and batches, the pool, and one env moving in 3D. Every value
// from the server, names from documents included, is written with textContent, never
// as markup.
import { SceneView } from './viewer.js';

const OVERVIEW_EVERY_MS = 1000;
const SCENE_EVERY_MS = 250;

const $ = (id) => document.getElementById(id);
const state = {
  loggedIn: false,
  selected: null, // { kind: 'batch' | 'env', id, index, n_envs }
  view: null,
  viewError: null,
  sceneBusy: false,
  overviewBusy: false,
  frames: 0,
  overviews: 0,
};

async function api(path, options = {}) {
  const response = await fetch(path, { credentials: 'same-origin', cache: 'no-store', ...options });
  let body = null;
  try { body = await response.json(); } catch { body = null; }
  return { status: response.status, body };
}

function element(tag, text, className) {
  const el = document.createElement(tag);
  if (text !== undefined) el.textContent = String(text);
  if (className) el.className = className;
  return el;
}

const number = (v, digits = 0) => (v === null || v === undefined ? '–'
  : Number(v).toLocaleString('en-US', { maximumFractionDigits: digits, minimumFractionDigits: digits }));
const rate = (v) => (v === null || v === undefined ? '–' : number(v, v < 100 ? 1 : 0));
const millis = (v) => (v === null || v === undefined ? '–' : `${number(v, v < 10 ? 2 : 1)} ms`);
const seconds = (v) => (v < 60 ? `${number(v, 0)} s` : v < 3600 ? `${number(v / 60, 0)} min` : `${number(v / 3600, 1)} h`);

function setStatus(text) { $('status').textContent = text ?? ''; }

function showLogin(message) {
  state.loggedIn = false;
  state.selected = null;
  $('main').hidden = true;
  $('login').hidden = false;
  $('logout').hidden = true;
  $('who').textContent = '';
  $('login-error').textContent = message ?? '';
  for (const id of ['batches', 'envs']) $(id).querySelector('tbody').replaceChildren();
  $('server').replaceChildren();
  $('bodies').replaceChildren();
  state.view?.clear();
}

function showMain(session) {
  state.loggedIn = true;
  $('login').hidden = true;
  $('main').hidden = false;
  $('logout').hidden = !session.auth;
  $('who').textContent = session.auth ? `tenant ${session.tenant}` : 'auth off: loopback only';
  if (!state.view && !state.viewError) {
    try {
      state.view = new SceneView($('view'));
    } catch (e) {
      state.viewError = `no 3D view: ${e.message}`;
      $('view-legend').textContent = state.viewError;
    }
  }
}

function select(kind, id, index = 0, n_envs = 1) {
  state.selected = { kind, id, index: Math.max(0, Math.min(index, n_envs - 1)), n_envs };
  $('view-index-label').hidden = kind !== 'batch';
  $('view-index').max = String(n_envs - 1);
  $('view-index').value = String(state.selected.index);
  $('view-title').textContent = kind === 'batch' ? `${id}, ` : id;
  pollScene();
}

// The selected env's keyframes and sensors, from its overview entry (at most 32 of each).
function fillDetails(item) {
  const list = (names) => names.length > 32 ? `${names.slice(0, 32).join(', ')}, … (${names.length})` : names.join(', ');
  const keyframes = item?.keyframes ?? [];
  const sensors = (item?.sensors ?? []).map((s) => `${s.name} (${s.type})`);
  $('view-details').textContent = [
    keyframes.length ? `keyframes: ${list(keyframes)}` : '',
    sensors.length ? `sensors: ${list(sensors)}` : '',
  ].filter((s) => s).join(' · ');
}

function row(kind, item) {
  const tr = document.createElement('tr');
  const selected = state.selected?.kind === kind && state.selected.id === item.id;
  if (selected) tr.className = 'selected';
  tr.dataset.id = item.id;
  for (const value of [item.id, number(item.n_envs), number(item.env_steps), rate(item.env_steps_per_s),
    rate(item.steps_per_s), number(item.episodes), millis(item.mean_step_ms), seconds(item.idle_s)]) {
    tr.appendChild(element('td', value));
  }
  const td = document.createElement('td');
  const button = element('button', 'view');
  button.type = 'button';
  button.addEventListener('click', () => select(kind, item.id, 0, item.n_envs));
  td.appendChild(button);
  tr.appendChild(td);
  return tr;
}

function fillTable(kind, list) {
  const body = $(kind === 'batch' ? 'batches' : 'envs').querySelector('tbody');
  const rows = list.items.map((item) => row(kind, item));
  if (rows.length === 0) {
    const tr = document.createElement('tr');
    const td = element('td', 'none', 'empty');
    td.colSpan = 9;
    tr.appendChild(td);
    rows.push(tr);
  }
  body.replaceChildren(...rows);
  const shown = list.items.length < list.total ? ` (first ${list.items.length} of ${list.total})` : ` (${list.total})`;
  $(kind === 'batch' ? 'batches-count' : 'envs-count').textContent = shown;
}

function fillServer(o) {
  const pairs = [
    ['version', o.server.version], ['pool threads', o.pool.threads],
    ['queue', number(o.pool.queue_depth)], ['pool jobs/s', rate(o.pool.jobs_per_s)],
    ['wait for a thread', millis(o.pool.mean_wait_ms)],
    ['since start', millis(o.pool.mean_wait_ms_since_start)],
    ['envs in batches', number(o.server.batch_envs)],
  ];
  $('server').replaceChildren(...pairs.map(([k, v]) => {
    const div = document.createElement('div');
    div.append(element('dt', k), element('dd', v));
    return div;
  }));
}

async function pollOverview() {
  if (!state.loggedIn || state.overviewBusy) return;
  state.overviewBusy = true;
  try {
    const { status, body } = await api('/api/overview');
    if (status === 401) { showLogin(body?.error); return; }
    if (status !== 200) { setStatus(body?.error ?? `overview: HTTP ${status}`); return; }
    setStatus('');
    const items = [...body.batches.items.map((i) => ['batch', i]), ...body.envs.items.map((i) => ['env', i])];
    const sel = state.selected;
    const still = sel && items.find(([k, i]) => k === sel.kind && i.id === sel.id);
    if (sel && !still) { state.selected = null; state.view?.clear(); $('view-title').textContent = `${sel.id} is closed`; }
    if (!state.selected && items.length > 0) select(items[0][0], items[0][1].id, 0, items[0][1].n_envs);
    const chosen = state.selected && items.find(([k, i]) => k === state.selected.kind && i.id === state.selected.id);
    fillDetails(chosen?.[1]);
    fillServer(body);
    fillTable('batch', body.batches);
    fillTable('env', body.envs);
    state.overviews += 1;
  } catch (e) {
    setStatus(`server unreachable (${e.message})`);
  } finally {
    state.overviewBusy = false;
  }
}

async function pollScene() {
  const sel = state.selected;
  if (!state.loggedIn || !sel || !state.view || state.sceneBusy || document.hidden) return;
  state.sceneBusy = true;
  const path = sel.kind === 'batch'
    ? `/api/batches/${encodeURIComponent(sel.id)}/envs/${sel.index}/scene`
    : `/api/envs/${encodeURIComponent(sel.id)}/scene`;
  try {
    const { status, body } = await api(path);
    if (sel !== state.selected) return;
    if (status === 401) { showLogin(body?.error); return; }
    if (status !== 200) { $('view-legend').textContent = body?.error ?? `scene: HTTP ${status}`; return; }
    const key = `${sel.kind}/${sel.id}/${sel.index}`;
    state.view.show(key, body);
    $('view-title').textContent = sel.kind === 'batch' ? `${sel.id}, ` : sel.id;
    $('view-legend').textContent = `${body.bodies.length} parts; grid ${state.view.spacing} mm; ` +
      'end effectors green, target magenta; drag to orbit';
    const names = [...new Set(body.bodies.map((b) => b.name))];
    $('bodies').replaceChildren(...names.map((n) => element('li', n)));
    state.frames += 1;
  } catch (e) {
    setStatus(`server unreachable (${e.message})`);
  } finally {
    state.sceneBusy = false;
  }
}

async function start() {
  const { status, body } = await api('/api/session');
  if (status !== 200) { setStatus(body?.error ?? `HTTP ${status}`); showLogin(body?.error); return; }
  if (!body.logged_in) { showLogin(); return; }
  showMain(body);
  await pollOverview();
}

$('login-form').addEventListener('submit', async (event) => {
  event.preventDefault();
  const token = $('token').value;
  const { status, body } = await api('/api/login', {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ token }),
  });
  $('token').value = '';
  if (status !== 200) { showLogin(body?.error ?? `HTTP ${status}`); return; }
  showMain(body);
  await pollOverview();
});

$('logout').addEventListener('click', async () => {
  await api('/api/logout', { method: 'POST' });
  showLogin();
});

$('view-index').addEventListener('change', () => {
  const sel = state.selected;
  if (sel?.kind === 'batch') select('batch', sel.id, Number($('view-index').value) | 0, sel.n_envs);
});

setInterval(pollOverview, OVERVIEW_EVERY_MS);
setInterval(pollScene, SCENE_EVERY_MS);

// For tests and for scripting the page.
window.dashboard = {
  get frames() { return state.frames; },
  get overviews() { return state.overviews; },
  get selected() { return state.selected && { ...state.selected }; },
  get canvas() { return state.view?.canvas ?? null; },
  get loggedIn() { return state.loggedIn; },
  select,
  ready: false,
};
await start();
window.dashboard.ready = true;
