// `moire serve` under bad input: malformed HTTP, bodies too long, messages that are not JSON
// or ask for what cannot be (unknown parameters, values out of range), a flood of slider
// messages, more event streams than it keeps. Each is answered with an error, the server keeps
// serving, and it writes nothing beside the scene.
'use strict';
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const net = require('node:net');
const path = require('node:path');
const {
  compareRgba,
  decodePng,
  tempDir,
  startServe,
  request,
  json,
  waitFor,
  render,
} = require('./serve_support.js');

let dir, cache, server;

before(async () => {
  dir = tempDir();
  const scene = path.join(dir, 'scene.moire');
  fs.writeFileSync(
    scene,
    'param gap = 6 in 2 .. 20\nscene { size = (320, 200) }\nlayer a { family = lines; spacing = gap; stroke = 1.5 }\n'
  );
  // The kernel cache, the one thing moire writes, in a folder of the test's own.
  cache = path.join(dir, 'cache');
  server = await startServe(scene, ['--paused', '--size', '320x200'], { MOIRE_CACHE_DIR: cache });
  await waitFor(async () => (await json(server, '/api/state')).body.frame, 30000, 'the first frame');
});

after(async () => {
  if (server) assert.equal(await server.stop(), 0, server.stderr());
  // Nothing written beside the scene: only the cache's folder is new.
  assert.deepEqual(fs.readdirSync(dir).sort(), ['cache', 'scene.moire']);
  if (dir) fs.rmSync(dir, { recursive: true, force: true });
});

async function stillServing() {
  const r = await json(server, '/api/state');
  assert.equal(r.status, 200);
  assert.ok(r.body.frame, 'a frame');
}

// Sends raw bytes and resolves with whatever comes back until an answer's head is complete
// or the server closes (or, with `hangUp`, until the client does, a moment after sending).
function raw(bytes, { hangUp = false } = {}) {
  return new Promise((resolve, reject) => {
    const u = new URL(server.base);
    const socket = net.connect(Number(u.port), u.hostname, () => {
      socket.write(bytes);
      if (hangUp) setTimeout(() => socket.destroy(), 100);
    });
    let reply = '';
    socket.on('data', (d) => {
      reply += d;
      // An answer's head is all the test reads: no need to wait for the server to close.
      if (reply.includes('\r\n\r\n')) socket.destroy();
    });
    socket.on('close', () => resolve(reply));
    socket.on('error', reject);
    socket.setTimeout(10000, () => socket.destroy(new Error('no answer in 10 s')));
  });
}

test('malformed HTTP is answered 400', async () => {
  for (const bytes of [
    'GARBAGE\r\n\r\n',
    `POST /api/view?token=${server.token} HTTP/1.1\r\nHost: x\r\nContent-Length: 99999999999\r\n\r\n`,
    'GET / HTTP/9\r\n\r\n',
    '\x00\x01\x02\x03\r\n\r\n',
  ]) {
    const reply = await raw(bytes);
    assert.match(reply, /^HTTP\/1\.1 4\d\d /, JSON.stringify(bytes));
  }
  // Half a request, then silence and a closed connection.
  await raw(`POST /api/view?token=${server.token} HTTP/1.1\r\nContent-Len`, { hangUp: true });
  await stillServing();
});

test('a body longer than the limit is refused unread', async () => {
  const r = await request(server, '/api/view', { method: 'POST', body: 'x'.repeat(200 * 1024) });
  assert.equal(r.status, 413);
  await stillServing();
});

test('messages that are not JSON, or ask for what cannot be, are answered with the reason', async () => {
  const cases = [
    ['/api/view', '{not json', /not JSON/],
    ['/api/view', '[1, 2]', /JSON object/],
    ['/api/view', {}, /asks for nothing/],
    ['/api/view', { frobnicate: 1 }, /unknown field 'frobnicate'/],
    ['/api/view', { view: 'sideways' }, /unknown view 'sideways'/],
    ['/api/view', { size: [0, 10] }, /size\[0\].*1 to/],
    ['/api/view', { size: [100.5, 10] }, /whole number/],
    ['/api/view', { zoom: { x: 1, y: 1, factor: 0 } }, /zoom factor/],
    ['/api/view', { zoom: { x: 1, y: 1, factor: 1e300 } }, /zoom factor/],
    ['/api/view', { zoom: { x: 'a', y: 1, factor: 2 } }, /'zoom.x' must be a number/],
    ['/api/view', { pan: { from: [0], to: [1, 1] } }, /pan.from/],
    ['/api/view', { overlay: 'yes' }, /overlay/],
    ['/api/clock', { play: 'yes' }, /'play' must be true or false/],
    ['/api/param', { name: 'nope', value: 1 }, /unknown parameter 'nope': the scene's are gap/],
    ['/api/param', { name: 'gap', value: 100 }, /^param 'gap' must be from 2 to 20, not 100$/],
    ['/api/param', { name: 'gap', value: -1e308 }, /^param 'gap' must be from 2 to 20/],
    ['/api/param', { name: 'gap', value: '#ffffff' }, /no text/],
    ['/api/param', { name: 'gap', value: [1, 2] }, /1 component, not 2/],
    ['/api/param', { name: 5, value: 1 }, /'name'/],
    ['/api/param', { name: 'gap' }, /'value' is missing/],
    ['/api/clock', { time: 'soon' }, /'time' must be a number/],
  ];
  for (const [pathname, body, message] of cases) {
    const r = await json(server, pathname, { method: 'POST', body });
    assert.equal(r.status, 400, JSON.stringify(body));
    assert.match(r.body.error, message);
  }
  const missing = await json(server, '/no/such/page');
  assert.equal(missing.status, 404);
  assert.equal((await request(server, '/frame/99999.png')).status, 404);
  await stillServing();
});

test('a flood of messages does not queue frames behind it', async () => {
  const start = (await json(server, '/api/state')).body;
  // Eight pages' worth of connections, each sending slider values as fast as the answers come.
  const t0 = Date.now();
  const worker = async () => {
    const replies = [];
    for (let i = 0; i < 125; ++i)
      replies.push(await json(server, '/api/param', { method: 'POST', body: { name: 'gap', value: 4 + (i % 50) / 10 } }));
    return replies;
  };
  const sends = Array.from({ length: 8 }, worker);
  const replies = (await Promise.all(sends)).flat();
  assert.equal(replies.length, 1000);
  assert.ok(replies.every((r) => r.status === 200));
  const last = Math.max(...replies.map((r) => r.body.version));
  // Every message was applied as it came. No frames queued behind them: the newest
  // state is on screen at most two frames later (the one in hand, then the newest).
  const atLast = (await json(server, '/api/state')).body;
  assert.equal(atLast.version, last);
  const state = await waitFor(async () => {
    const s = (await json(server, '/api/state')).body;
    return s.shownVersion >= last ? s : null;
  }, 30000, 'the newest version on screen');
  const frames = state.frame.id - start.frame.id;
  console.log(`1000 slider messages in ${Date.now() - t0} ms made ${frames} frames`);
  assert.ok(state.frame.id - atLast.frame.id <= 2, `${state.frame.id - atLast.frame.id} frames after`);
  await stillServing();
});

test('event streams beyond the limit are refused, and a closed one frees its place', async () => {
  const controllers = [];
  const statuses = [];
  for (let i = 0; i < 6; ++i) {
    const c = new AbortController();
    controllers.push(c);
    const url = new URL('/api/events', server.base);
    url.searchParams.set('token', server.token);
    const r = await fetch(url, { signal: c.signal });
    statuses.push(r.status);
    if (r.status !== 200) await r.text();
  }
  assert.deepEqual(statuses, [200, 200, 200, 200, 503, 503]);
  for (const c of controllers) c.abort();
  // The server notices the closed streams at their next heartbeat.
  await waitFor(async () => {
    const url = new URL('/api/events', server.base);
    url.searchParams.set('token', server.token);
    const c = new AbortController();
    const r = await fetch(url, { signal: c.signal });
    c.abort();
    return r.status === 200;
  }, 10000, 'a free stream');
  await stillServing();
});

test('--filter: the served frame is what render --filter draws', async () => {
  // Circles 0.7 apart and 0.1 wide at a world unit a pixel: 14% ink under the mean filter,
  // solid ink point-sampled (docs/filtering.md).
  const scene = path.join(dir, 'fine.moire');
  fs.writeFileSync(scene, 'layer a { family = circles; spacing = 0.7; stroke = 0.1 }\n');
  const ink = {};
  try {
    for (const filter of ['point', 'mean']) {
      const fine = await startServe(scene, ['--paused', '--size', '160x120', '--filter', filter], {
        MOIRE_CACHE_DIR: cache,
      });
      try {
        const state = await waitFor(async () => (await json(fine, '/api/state')).body.frame, 30000, 'a frame');
        const response = await request(fine, `/frame/${state.id}.png`);
        assert.equal(response.status, 200);
        const frame = decodePng(Buffer.from(await response.arrayBuffer()));
        const want = render(scene, 160, 120, ['--filter', filter]);
        const d = compareRgba(frame.rgba, want.rgba);
        assert.ok(d.max <= 1, `${filter}: ${d.differing} pixels differ, by up to ${d.max}`);
        let sum = 0;
        for (let i = 0; i < frame.rgba.length; i += 4) sum += 1 - frame.rgba[i] / 255;
        ink[filter] = sum / (frame.rgba.length / 4);
      } finally {
        assert.equal(await fine.stop(), 0, fine.stderr());
      }
    }
  } finally {
    fs.rmSync(scene);
  }
  assert.ok(ink.mean < 0.3, `mean ink ${ink.mean}`);
  assert.ok(ink.point > 0.9, `point ink ${ink.point}`);
});
