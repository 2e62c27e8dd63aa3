// skillweb's page: the state stream drives the 3D view, the status, the map and the plots; the
// buttons post calls to skillweb, which makes them to skilld with this page's control lease.
// With logins the page first asks for one; an observer's controls are disabled, saying why.
import { MapView } from './map_view.js';
import { RollingPlot } from './plots.js';
import { RobotView } from './robot_view.js';

const $ = (id) => document.getElementById(id);
const LEGS = [['FR', '#dc2626'], ['FL', '#2563eb'], ['RR', '#16a34a'], ['RL', '#9333ea']];

async function getJson(path) {
  const r = await fetch(path);
  if (!r.ok) throw new Error(`${path}: ${r.status}`);
  return r.json();
}

// This page's session: its user, role and CSRF token; null until logged in.
let session = null;
let leaving = false;  // logged out: the page reloads itself

// POSTs JSON to skillweb; the CSRF token goes with it, as skillweb requires of a command.
function post(path, args) {
  return fetch(path, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json', 'X-CSRF-Token': session?.csrf ?? '' },
    body: JSON.stringify(args),
  });
}

// The session, or null when skillweb wants a login first.
async function fetchSession() {
  const s = await getJson('/api/session');
  return s.logged_in ? s : null;
}

// A call to skilld through skillweb; the reply's status and message go under the controls.
async function call(name, args = {}) {
  const out = $('reply');
  out.textContent = `${name}…`;
  out.className = 'reply';
  try {
    const reply = await (await post(`/api/${name}`, args)).json();
    out.textContent = `${name}: ${reply.status}${reply.message ? ` – ${reply.message}` : ''}`;
    if (!reply.ok) out.className = 'reply refused';
  } catch (e) {
    out.textContent = `${name}: skillweb unreachable`;
    out.className = 'reply refused';
  }
}

function fillSkills(skills) {
  const select = $('skill');
  for (const k of skills) {
    const [vx, vy] = k.linear_velocity;
    const option = new Option(`${k.id}: ${vx.toFixed(2)}, ${vy.toFixed(2)} m/s, wz ${k.angular_velocity[2].toFixed(2)}`, k.id);
    option.dataset.speed = Math.hypot(vx, vy);
    option.dataset.survival = k.survival_steps;
    select.add(option);
  }
}

function showStatus(s, clientId) {
  const fmt = (v, n = 2) => v.map((x) => x.toFixed(n)).join(', ');
  const task = s.task.call ? `${s.task.call} ${s.task.state} ${s.task.elapsed.toFixed(1)} s${s.task.message ? ` (${s.task.message})` : ''}` : '–';
  const rows = {
    mode: s.mode,
    skill: s.skill < 0 ? '–' : s.mode === 'stand' ? `${s.skill}, braking the last motion` : s.skill,
    task,
    control: s.controller ? (s.controller === clientId ? `this page (${s.controller})` : s.controller) : 'nobody',
    faults: s.faults ? s.fault_message || `0x${s.faults.toString(16)}` : 'none',
    position: `${fmt(s.position)} m`,
    velocity: `${fmt(s.linear_velocity)} m/s, wz ${s.angular_velocity[2].toFixed(2)}`,
    time: `${s.time.toFixed(2)} s, tick ${s.tick}, ${s.backend}`,
  };
  $('status').replaceChildren(...Object.entries(rows).flatMap(([k, v]) => {
    const dt = document.createElement('dt'), dd = document.createElement('dd');
    dt.textContent = k;
    dd.textContent = v;
    dd.id = `status-${k}`;
    return [dt, dd];
  }));
  $('mode').textContent = s.skill < 0 ? s.mode : s.mode === 'stand' ? `${s.mode}, braking` : `${s.mode} ${s.skill}`;
  $('mode').className = `badge ${s.mode === 'damp' ? 'damp' : ''}`;
  $('fault').hidden = !s.faults;
  $('fault').textContent = `Safety stop: ${s.fault_message}`;
}

// Who this page is in the header; an observer's controls disabled, with the reason.
function showSession() {
  $('who').hidden = $('logout').hidden = !session.logins;
  $('who').textContent = `${session.user} · ${session.role}`;
  $('logout').onclick = async () => {
    leaving = true;
    await post('/api/logout', {});
    location.reload();
  };
  if (session.can_command) return;
  for (const control of document.querySelectorAll('main button:not(#logout), #damp')) {
    control.disabled = true;
    control.title = session.reason;
  }
  $('role-note').hidden = false;
  $('role-note').textContent = session.reason;
}

// The login form; the page starts once skillweb has opened a session.
function askLogin() {
  $('login').hidden = false;
  $('login').onsubmit = async (e) => {
    e.preventDefault();
    const r = await post('/api/login', { name: $('login-name').value, password: $('login-password').value });
    const reply = await r.json();
    if (!r.ok) {
      $('login-reply').textContent = reply.message;
      return;
    }
    session = reply;
    $('login').hidden = true;
    await start();
  };
}

async function start() {
  $('login').hidden = true;
  document.querySelector('main').hidden = false;
  showSession();
  const [info, urdf] = await Promise.all([getJson('/api/info'), fetch('/a1.urdf').then((r) => r.text())]);
  // An observer's client makes no calls to skilld, not even for the skills.
  if (session.can_command) {
    getJson('/api/skills').then(fillSkills).catch(() => ($('reply').textContent = 'skills: no answer from skilld'));
  }

  const view = new RobotView($('scene'), urdf);
  const map = new MapView($('map'), info.map, (x, y) => (session.can_command ? call('navigate', { x, y }) : null));
  const axes = [['vx', '#dc2626'], ['vy', '#16a34a'], ['wz', '#2563eb']];
  const velocity = new RollingPlot($('velocity-plot'), { colors: axes.map(([, c]) => c), legend: axes });
  const joints = new RollingPlot($('joint-plot'), { colors: info.joint_names.map((_, i) => LEGS[Math.floor(i / 3)][1]), legend: LEGS });
  const page = { view, info, session, state: null, received: 0, delays: [] };
  window.skillweb = page;  // for the browser tests and the benchmark: the scene, the newest sample, delays

  $('damp').onclick = () => call('damp');
  for (const name of ['stand', 'stop', 'reset', 'clear_stop', 'release_control']) $(name).onclick = () => call(name);
  $('skill-form').onsubmit = (e) => {
    e.preventDefault();
    call('execute_skill', { skill: Number($('skill').value), duration: Number($('skill-duration').value) });
  };
  $('velocity-form').onsubmit = (e) => {
    e.preventDefault();
    const n = (id) => Number($(id).value);
    call('track_velocity', { vx: n('vx'), vy: n('vy'), wz: n('wz'), duration: n('velocity-duration') });
  };

  const events = new EventSource('/api/events');
  events.onmessage = (e) => {
    const s = JSON.parse(e.data);
    page.state = s;
    page.received += 1;
    // From skillweb having the sample to the page having it (one clock: skillweb on this machine).
    page.delays.push(performance.timeOrigin + performance.now() - s.received);
    if (page.delays.length > 5000) page.delays.shift();
    view.show(s, info.joint_names);
    map.update(s);
    velocity.add(s.time, [s.linear_velocity[0], s.linear_velocity[1], s.angular_velocity[2]]);
    joints.add(s.time, s.joint_position);
    $('link').textContent = `live ${page.delays[page.delays.length - 1].toFixed(1)} ms`;
    $('link').className = 'badge on';
  };
  events.onerror = () => {
    $('link').textContent = 'reconnecting';
    $('link').className = 'badge off';
    // A session that ended (logout elsewhere, expiry) needs a new login, not a reconnection.
    if (!leaving) fetchSession().then((s) => s || location.reload()).catch(() => {});
  };
  // Text and 2-D drawings at the screen's rate, not the stream's.
  const draw = () => {
    if (page.state) showStatus(page.state, info.client_id);
    map.draw();
    velocity.draw();
    joints.draw();
    requestAnimationFrame(draw);
  };
  requestAnimationFrame(draw);
  // No sample for a second: say so rather than show a stale robot as live.
  setInterval(() => {
    if (page.received === page.lastCount) {
      $('link').textContent = 'no state';
      $('link').className = 'badge off';
    }
    page.lastCount = page.received;
  }, 1000);
  page.ready = true;
}

async function boot() {
  session = await fetchSession();
  return session ? start() : askLogin();
}

boot().catch((e) => {
  $('reply').textContent = `skillweb: ${e.message}`;
  throw e;
});
