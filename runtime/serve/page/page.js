// The page of `moire serve`. It follows the session's state through server-sent events
// (/api/events), fetches each new frame's bytes by id and puts them into the canvas, and sends
// the controls' changes as small JSON messages. Every request carries the run's token.
'use strict';

const token = new URLSearchParams(location.search).get('token') || '';
const withToken = (path) =>
  path + (path.includes('?') ? '&' : '?') + 'token=' + encodeURIComponent(token);

const $ = (id) => document.getElementById(id);
const canvas = $('picture');
const box = $('picture-box');
const context = canvas.getContext('2d', { alpha: true });

// What tests and the VS Code preview read: the state last received and the frame on screen.
const moire = (window.moire = { state: null, shown: { id: 0, version: 0 }, errors: [] });

// --- Messages -------------------------------------------------------------------------------

async function post(path, body) {
  const response = await fetch(withToken(path), {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(body),
  });
  let reply = {};
  try {
    reply = await response.json();
  } catch (e) {
    reply = { error: `HTTP ${response.status}` };
  }
  if (!response.ok) throw new Error(reply.error || `HTTP ${response.status}`);
  return reply;
}

// One message of a kind in flight at a time; while it is, only the newest next one is kept.
// A slider dragged fast sends its newest value, not every value it passed.
// `onIdle` runs once the last message is answered.
function latestOnly(send, onIdle = () => {}) {
  let inFlight = false;
  let waiting = false; // a next message is kept (its body may be null: a parameter's reset)
  let next;
  const pump = async () => {
    if (inFlight || !waiting) return;
    const body = next;
    waiting = false;
    inFlight = true;
    try {
      await send(body);
    } finally {
      inFlight = false;
      if (waiting) pump();
      else onIdle();
    }
  };
  const sender = (body) => {
    next = body;
    waiting = true;
    pump();
  };
  // A message in flight or waiting: the server's state does not yet show the newest.
  sender.busy = () => inFlight || waiting;
  return sender;
}

function report(error) {
  moire.errors.push(String(error.message || error));
  $('status').textContent = String(error.message || error);
}

// --- Frames ---------------------------------------------------------------------------------

let wantedFrame = 0;

async function showFrame(frame) {
  if (!frame || frame.id === moire.shown.id || frame.id === wantedFrame) {
    if (frame && frame.id === moire.shown.id) {
      moire.shown.version = Math.max(moire.shown.version, frame.version);
      settleGestures(frame.version);
    }
    return;
  }
  wantedFrame = frame.id;
  try {
    // The frame's bytes as they are (what moire render writes into a PNG): no decoding, no
    // colour management.
    const response = await fetch(withToken(`/frame/${frame.id}.rgba`));
    if (!response.ok) return; // replaced already: the newer one is on its way
    const width = Number(response.headers.get('X-Frame-Width'));
    const height = Number(response.headers.get('X-Frame-Height'));
    const bytes = new Uint8ClampedArray(await response.arrayBuffer());
    if (frame.id < moire.shown.id || bytes.length !== width * height * 4) return;
    if (canvas.width !== width || canvas.height !== height) {
      canvas.width = width;
      canvas.height = height;
    }
    context.putImageData(new ImageData(bytes, width, height), 0, 0);
    moire.shown = { id: frame.id, version: frame.version, width: frame.width, height: frame.height };
    canvas.dataset.frame = String(frame.id);
    $('waiting').hidden = true;
    settleGestures(frame.version);
  } catch (e) {
    report(e);
  } finally {
    if (wantedFrame === frame.id) wantedFrame = 0;
  }
}

// --- Zoom and pan ---------------------------------------------------------------------------
// Each gesture goes to the server at once and moves the picture on screen at once (a CSS
// transform of the last frame); once a frame that includes the gesture arrives, its part of
// the transform goes.

let gestures = []; // {matrix, version (once the server answered)}

function applyGestures() {
  let m = new DOMMatrix();
  for (const g of gestures) m = g.matrix.multiply(m);
  canvas.style.transform = m.isIdentity ? '' : m.toString();
}

function settleGestures(version) {
  const before = gestures.length;
  gestures = gestures.filter((g) => g.version === undefined || g.version > version);
  if (gestures.length !== before) applyGestures();
}

// A position on screen as the frame's pixels (the canvas may be shown scaled).
function framePoint(clientX, clientY) {
  const r = canvas.getBoundingClientRect();
  const base = gestures.reduce((m, g) => g.matrix.multiply(m), new DOMMatrix());
  // Undo the on-screen transform: the server's frame has none.
  const p = base.inverse().transformPoint(new DOMPoint(clientX - r.left + 0, clientY - r.top));
  const sx = canvas.width / (canvas.offsetWidth || 1);
  const sy = canvas.height / (canvas.offsetHeight || 1);
  return [p.x * sx, p.y * sy];
}

function gesture(matrix, message) {
  const g = { matrix };
  gestures.push(g);
  applyGestures();
  post('/api/view', message)
    .then((reply) => {
      g.version = reply.version;
      if (reply.version <= moire.shown.version) settleGestures(moire.shown.version);
    })
    .catch((e) => {
      gestures = gestures.filter((x) => x !== g);
      applyGestures();
      report(e);
    });
}

box.addEventListener(
  'wheel',
  (event) => {
    event.preventDefault();
    const factor = Math.pow(1.1, -event.deltaY / 100);
    const [x, y] = framePoint(event.clientX, event.clientY);
    const r = canvas.getBoundingClientRect();
    const cx = event.clientX - r.left, cy = event.clientY - r.top;
    const m = new DOMMatrix().translate(cx, cy).scale(factor).translate(-cx, -cy);
    gesture(m, { zoom: { x, y, factor } });
  },
  { passive: false }
);

let drag = null;
box.addEventListener('pointerdown', (event) => {
  if (event.button !== 0) return;
  drag = { x: event.clientX, y: event.clientY };
  box.setPointerCapture(event.pointerId);
  box.classList.add('dragging');
});
box.addEventListener('pointermove', (event) => {
  if (!drag) return;
  const dx = event.clientX - drag.x, dy = event.clientY - drag.y;
  if (dx === 0 && dy === 0) return;
  const from = framePoint(drag.x, drag.y);
  const to = framePoint(event.clientX, event.clientY);
  drag = { x: event.clientX, y: event.clientY };
  gesture(new DOMMatrix().translate(dx, dy), { pan: { from, to } });
});
const endDrag = () => {
  drag = null;
  box.classList.remove('dragging');
};
box.addEventListener('pointerup', endDrag);
box.addEventListener('pointercancel', endDrag);

$('reset-view').addEventListener('click', () => {
  gestures = [];
  applyGestures();
  post('/api/view', { reset: true }).catch(report);
});

// The frame is drawn at the picture box's size in device pixels, unless --size fixed it.
let lastSize = '';
function sendSize() {
  if (moire.state && moire.state.fixedSize) return;
  const dpr = window.devicePixelRatio || 1;
  const w = Math.max(1, Math.round(box.clientWidth * dpr));
  const h = Math.max(1, Math.round(box.clientHeight * dpr));
  const key = `${w}x${h}`;
  if (key === lastSize) return;
  lastSize = key;
  post('/api/view', { size: [w, h] }).catch(report);
}
let sizeTimer = 0;
new ResizeObserver(() => {
  clearTimeout(sizeTimer);
  sizeTimer = setTimeout(sendSize, 120);
}).observe(box);

// --- The view and the clock -----------------------------------------------------------------

function buildViewModes(state) {
  const holder = $('view-modes');
  if (holder.childElementCount) return;
  for (const name of ['scene', ...state.views]) {
    const label = document.createElement('label');
    const input = document.createElement('input');
    input.type = 'radio';
    input.name = 'view';
    input.value = name;
    input.addEventListener('change', () => post('/api/view', { view: name }).catch(report));
    label.append(input, name === 'scene' ? "scene's" : name);
    holder.append(label);
  }
}

$('overlay').addEventListener('change', (e) =>
  post('/api/view', { overlay: e.target.checked }).catch(report)
);

$('play').addEventListener('click', () =>
  post('/api/clock', { play: !(moire.state && moire.state.playing) }).catch(report)
);
document.addEventListener('keydown', (e) => {
  if (e.key === ' ' && !(e.target instanceof HTMLInputElement)) {
    e.preventDefault();
    $('play').click();
  }
});
const seek = latestOnly((time) => post('/api/clock', { time, play: false }).catch(report));
$('scrub').addEventListener('input', (e) => seek(Number(e.target.value)));

// --- Parameters -----------------------------------------------------------------------------

const sendParameter = new Map(); // name -> latestOnly sender
const parameterControls = new Map(); // name -> update(values) from the state
let parameterSignature = '';

function parameterSender(name) {
  if (!sendParameter.has(name)) {
    let answered = 0; // the version the last answer named
    sendParameter.set(
      name,
      latestOnly(
        (value) =>
          post('/api/param', { name, value })
            .then((reply) => {
              answered = reply.version;
              $('param-error').hidden = true;
            })
            .catch((e) => {
              $('param-error').textContent = e.message;
              $('param-error').hidden = false;
            }),
        // The state may have come before the answer: its value goes into the controls now
        // (a state older than the answer would move a control back; the next one will do).
        () => {
          if (!moire.state || moire.state.version < answered) return;
          const p = (moire.state.params || []).find((q) => q.name === name);
          if (p) parameterControls.get(name)?.(p.value);
        }
      )
    );
  }
  return sendParameter.get(name);
}

const toDegrees = (p) => p.type === 'angle' && p.unit === 'deg';
// Degrees to twelve digits: 30deg reads 30 on the slider, not 29.999999999999996.
const shownValue = (p, v) => (toDegrees(p) ? +((v * 180) / Math.PI).toPrecision(12) : v);
const sentValue = (p, v) => (toDegrees(p) ? (v * Math.PI) / 180 : v);
const hex2 = (v) => Math.round(Math.min(1, Math.max(0, v)) * 255).toString(16).padStart(2, '0');

function slider(p, component, value, onInput) {
  const input = document.createElement('input');
  input.type = 'range';
  const lo = p.min ?? Math.min(0, value);
  const hi = p.max ?? Math.max(1, value * 2 || 1);
  input.min = String(shownValue(p, lo));
  input.max = String(shownValue(p, hi));
  input.step = p.step != null ? String(shownValue(p, p.step)) : 'any';
  input.value = String(shownValue(p, value));
  input.dataset.param = p.name;
  input.dataset.component = String(component);
  input.addEventListener('input', () => onInput(sentValue(p, Number(input.value)), input));
  return input;
}

function buildParameters(params) {
  const list = $('param-list');
  list.textContent = '';
  parameterControls.clear();
  if (!params.length) {
    const none = document.createElement('p');
    none.className = 'hint';
    none.textContent = 'This scene declares no parameters.';
    list.append(none);
    return;
  }
  for (const p of params) {
    const row = document.createElement('div');
    row.className = 'param';
    row.dataset.param = p.name;
    const send = parameterSender(p.name);
    const title = document.createElement('div');
    title.className = 'name';
    const name = document.createElement('span');
    name.textContent = p.name;
    const shown = document.createElement('output');
    const reset = document.createElement('button');
    reset.type = 'button';
    reset.className = 'reset';
    reset.textContent = '↺';
    reset.title = "The scene's own value";
    // Back to the scene's value, which the state that follows brings into the controls.
    reset.addEventListener('click', () => send(null));
    title.append(name, shown, reset);
    row.append(title);
    const value = p.value.slice();
    const show = () => {
      const unit = toDegrees(p) ? '°' : p.label ? ` ${p.label}` : '';
      shown.textContent =
        p.type === 'color'
          ? '#' + value.slice(0, 3).map(hex2).join('')
          : p.type === 'bool'
          ? value[0] ? 'true' : 'false'
          : value.map((v) => +shownValue(p, v).toFixed(4) + unit).join(', ');
    };
    if (p.type === 'bool') {
      const box = document.createElement('input');
      box.type = 'checkbox';
      box.checked = value[0] !== 0;
      box.dataset.param = p.name;
      box.addEventListener('change', () => {
        value[0] = box.checked ? 1 : 0;
        show();
        send(box.checked);
      });
      title.prepend(box);
    } else if (p.type === 'color') {
      const picker = document.createElement('input');
      picker.type = 'color';
      picker.value = '#' + value.slice(0, 3).map(hex2).join('');
      picker.dataset.param = p.name;
      picker.addEventListener('input', () => {
        const h = picker.value;
        for (let i = 0; i < 3; ++i) value[i] = parseInt(h.substr(1 + 2 * i, 2), 16) / 255;
        show();
        send(value.slice());
      });
      row.append(picker);
    } else {
      const holder = document.createElement('div');
      if (value.length > 1) holder.className = 'vector';
      value.forEach((v, i) => {
        if (value.length > 1) holder.append('xyzw'[i]);
        holder.append(
          slider(p, i, v, (sent) => {
            value[i] = sent;
            show();
            send(value.slice());
          })
        );
      });
      row.append(holder);
    }
    show();
    // The server's value (another page's slider, a reset, a save) into the controls, once
    // every message this page sent about the parameter is answered: until then the state may
    // be older than the hand.
    parameterControls.set(p.name, (values) => {
      if (!values || values.length !== value.length || values.some((v) => v === null)) return;
      if (send.busy()) return;
      values.forEach((v, i) => (value[i] = v));
      for (const input of row.querySelectorAll('input')) {
        if (input.type === 'range') input.value = String(shownValue(p, value[Number(input.dataset.component)]));
        else if (input.type === 'checkbox') input.checked = value[0] !== 0;
        else if (input.type === 'color') input.value = '#' + value.slice(0, 3).map(hex2).join('');
      }
      show();
    });
    list.append(row);
  }
}

// --- The state ------------------------------------------------------------------------------

function showState(state) {
  moire.state = state;
  $('scene-name').textContent = state.scene.split('/').pop();
  document.title = `${state.scene.split('/').pop()} - moire serve`;
  buildViewModes(state);
  for (const input of document.querySelectorAll('#view-modes input'))
    input.checked = input.value === state.view;
  $('overlay').checked = state.overlay === true;
  $('play').textContent = state.playing ? 'Pause' : 'Play';
  if (!state.playing || document.activeElement !== $('scrub')) {
    const scrub = $('scrub');
    if (state.time > Number(scrub.max)) scrub.max = String(Math.ceil(state.time / 10) * 10);
    if (document.activeElement !== scrub) scrub.value = String(state.time);
  }
  $('time-value').textContent = `${state.time.toFixed(2)} s`;

  const text = [state.errors, state.frameError].filter(Boolean).join('\n');
  $('errors').textContent = text;
  $('errors').hidden = !text;

  const params = state.params || [];
  const signature = JSON.stringify(params.map((p) => [p.name, p.type, p.min, p.max, p.step, p.unit]));
  if (signature !== parameterSignature) {
    parameterSignature = signature;
    buildParameters(params);
  } else {
    for (const p of params) parameterControls.get(p.name)?.(p.value);
  }

  const f = state.frame;
  $('status').textContent = f
    ? `${f.width}×${f.height} · ${f.reused ? 'unchanged' : `${Math.round(f.renderMs)} ms`} · ${state.backend}`
    : state.backend;
  if (!state.fixedSize) sendSize();
  showFrame(f);
}

const events = new EventSource(withToken('/api/events'));
events.addEventListener('state', (event) => showState(JSON.parse(event.data)));
events.addEventListener('error', () => {
  $('status').textContent = 'Lost the server: is moire serve still running?';
});
