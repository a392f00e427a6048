// `moire serve` in a real browser: the page shows what `moire render` draws, its sliders what
// `moire render -D` draws, it follows saves (a bad one shows its located diagnostic over the
// last picture; the fix brings a picture back), and the server refuses requests without the
// run's token.
//
// MOIRE_SCREENSHOT=path.png also saves a screenshot of the page (docs/images/serve.png).
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
  launchBrowser,
} = require('./serve_support.js');

// `stroke` as ';' makes a scene with an error on line 14, column 14.
const scene = (gap, stroke = '1.8') => `param gap = ${gap} in 4 .. 12 step 0.5
param tilt = 8deg in 0deg .. 30deg step 0.5deg
param ink = #141418
param bold = false

scene {
    size = (640, 400)
    background = #f6f3ec
}

layer left {
    family = circles
    spacing = gap
    stroke = ${stroke}
    color = ink
    origin = (-30, 0)
}

layer right {
    family = lines
    spacing = gap * 0.8
    stroke = select(bold, 2.6, 1.6)
    color = ink
    rotation = tilt
}
`;
const broken = scene(7, ';');

let dir, scenePath, server, browser, page;

before(async () => {
  dir = tempDir();
  scenePath = path.join(dir, 'rings.moire');
  fs.writeFileSync(scenePath, scene(7));
  server = await startServe(scenePath, ['--paused']);
  browser = await launchBrowser();
  page = await browser.newPage();
  await page.setViewport({ width: 960, height: 560, deviceScaleFactor: 1 });
  page.on('pageerror', (e) => console.error('page error:', e.message));
  await page.goto(server.url);
});

after(async () => {
  if (browser) await browser.close();
  if (server) assert.equal(await server.stop(), 0, server.stderr());
  if (dir) fs.rmSync(dir, { recursive: true, force: true });
});

// Waits until the page shows the newest frame at the size it asked for, and returns the
// canvas's pixels with that frame's id and size.
async function shownFrame(after = 0) {
  await page.waitForFunction(
    (after) => {
      const m = window.moire;
      const s = m.state;
      return (
        s && s.frame && !s.fixedSize && s.frame.id > after && m.shown.id === s.frame.id &&
        s.frame.version === s.version && s.frame.width === s.size[0] && s.frame.height === s.size[1]
      );
    },
    { timeout: 60000 },
    after
  );
  return page.evaluate(() => {
    const c = document.getElementById('picture');
    const pixels = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    return { id: window.moire.shown.id, width: c.width, height: c.height, rgba: Array.from(pixels) };
  });
}

test('a request without the token, or with another, is refused', async () => {
  for (const pathname of ['/', '/api/state', '/api/events', '/page.js', '/frame/1.png']) {
    assert.equal((await request(server, pathname, { token: null })).status, 403, pathname);
    assert.equal((await request(server, pathname, { token: 'f'.repeat(32) })).status, 403, pathname);
  }
  const refused = await json(server, '/api/view', { method: 'POST', body: { reset: true }, token: null });
  assert.equal(refused.status, 403);
  assert.match(refused.body.error, /token/);
  assert.equal((await request(server, '/api/state')).status, 200);
});

// Two requests, one after the other on one connection: a POST without the token whose body
// comes a little after its head, as a browser may send it, then a GET with the token. A server
// that refused the POST on its head alone would take the late body as the start of the next
// request and answer that 400.
test('a refused POST leaves its kept-alive connection ready for the next request', async () => {
  const u = new URL(server.base);
  const body = JSON.stringify({ reset: true });
  const head =
    `POST /api/view HTTP/1.1\r\nHost: ${u.host}\r\nContent-Type: application/json\r\n` +
    `Content-Length: ${body.length}\r\n\r\n`;
  const get = `GET /api/state?token=${server.token} HTTP/1.1\r\nHost: ${u.host}\r\nConnection: close\r\n\r\n`;
  const reply = await new Promise((resolve, reject) => {
    let data = '';
    let bodySent = false;
    let getSent = false;
    // The GET once the body is out and the refusal has come whole (its JSON body with it).
    const next = () => {
      if (!getSent && bodySent && data.includes('serve printed"}')) {
        getSent = true;
        socket.write(get);
      }
    };
    const socket = net.connect(Number(u.port), u.hostname, () => {
      socket.write(head);
      setTimeout(() => {
        socket.write(body);
        bodySent = true;
        next();
      }, 200);
    });
    socket.on('data', (d) => {
      data += d;
      next();
    });
    socket.on('end', () => resolve(data));
    socket.on('error', reject);
  });
  const statuses = [...reply.matchAll(/HTTP\/1\.1 (\d{3})/g)].map((m) => m[1]);
  assert.deepEqual(statuses, ['403', '200'], reply.slice(0, 600));
});

let first;
test('the page shows the pixels moire render draws at the same size', async () => {
  first = await shownFrame();
  // The picture fills what the panel leaves of the window.
  assert.ok(first.width > 500 && first.height > 500, `${first.width}x${first.height}`);
  const reference = render(scenePath, first.width, first.height);
  const d = compareRgba(Uint8Array.from(first.rgba), reference.rgba);
  assert.equal(d.max, 0, `${d.differing} pixels differ, by up to ${d.max}`);
});

test('a broken save shows its located diagnostic over the last picture; the fix brings a new one', async () => {
  fs.writeFileSync(scenePath, broken);
  await page.waitForFunction(
    () => !document.getElementById('errors').hidden,
    { timeout: 30000 }
  );
  const text = await page.$eval('#errors', (e) => e.textContent);
  assert.match(text, /rings\.moire:14:14: error: /);
  assert.match(text, /\^/); // the caret under the place
  const still = await page.evaluate(() => ({
    id: window.moire.shown.id,
    shown: getComputedStyle(document.getElementById('picture')).display !== 'none',
  }));
  assert.deepEqual(still, { id: first.id, shown: true });

  fs.writeFileSync(scenePath, scene(9));
  await page.waitForFunction(() => document.getElementById('errors').hidden, { timeout: 30000 });
  const fixed = await shownFrame(first.id);
  const reference = render(scenePath, fixed.width, fixed.height);
  const d = compareRgba(Uint8Array.from(fixed.rgba), reference.rgba);
  assert.equal(d.max, 0, `${d.differing} pixels differ, by up to ${d.max}`);
});

test('dragging a slider draws what moire render -D draws for its value', async () => {
  const before = (await shownFrame()).id;
  const slider = await page.waitForSelector('input[type=range][data-param=gap]');
  assert.equal(await slider.evaluate((e) => [e.min, e.max, e.step, e.value].join(' ')), '4 12 0.5 9');
  const r = await slider.boundingBox();
  // From the thumb (9 of 4 .. 12) to three quarters of the way: a drag, many values on the way.
  const y = r.y + r.height / 2;
  await page.mouse.move(r.x + r.width * (5 / 8), y);
  await page.mouse.down();
  for (let i = 1; i <= 10; ++i) await page.mouse.move(r.x + r.width * (5 / 8 + (i / 10) * (-3 / 8)), y);
  await page.mouse.up();
  const value = await slider.evaluate((e) => e.value);
  assert.notEqual(value, '9');
  // The newest frame shows the slider's last value, and the state says so.
  await page.waitForFunction(
    (v) => {
      const p = (window.moire.state.params || []).find((p) => p.name === 'gap');
      return p && p.set && String(p.value[0]) === v;
    },
    { timeout: 30000 },
    value
  );
  const dragged = await shownFrame(before);
  const reference = render(scenePath, dragged.width, dragged.height, ['-D', `gap=${value}`]);
  const d = compareRgba(Uint8Array.from(dragged.rgba), reference.rgba);
  assert.equal(d.max, 0, `gap=${value}: ${d.differing} pixels differ, by up to ${d.max}`);

  // A value out of range, as a message: refused with the reason.
  const refused = await json(server, '/api/param', { method: 'POST', body: { name: 'gap', value: 40 } });
  assert.equal(refused.status, 400);
  assert.equal(refused.body.error, "param 'gap' must be from 4 to 12, not 40");
  const unknown = await json(server, '/api/param', { method: 'POST', body: { name: 'gape', value: 5 } });
  assert.equal(unknown.status, 400);
  assert.match(unknown.body.error, /unknown parameter 'gape'/);
});

test('the angle slider shows degrees; the checkbox and the colour picker draw what -D draws', async () => {
  const tilt = await page.waitForSelector('input[type=range][data-param=tilt]');
  assert.equal(await tilt.evaluate((e) => [e.min, e.max, e.step, e.value].join(' ')), '0 30 0.5 8');
  const gap = await page.evaluate(() => window.moire.state.params.find((p) => p.name === 'gap').value[0]);
  let before = (await shownFrame()).id;
  await page.click('input[type=checkbox][data-param=bold]');
  await page.$eval('input[type=color][data-param=ink]', (e) => {
    e.value = '#a02030';
    e.dispatchEvent(new Event('input', { bubbles: true }));
  });
  await page.waitForFunction(
    () => {
      const ps = window.moire.state.params;
      return ps.find((p) => p.name === 'bold').set && ps.find((p) => p.name === 'ink').set;
    },
    { timeout: 30000 }
  );
  const frame = await shownFrame(before);
  const args = ['-D', `gap=${gap}`, '-D', 'bold=true', '-D', 'ink=#a02030'];
  const reference = render(scenePath, frame.width, frame.height, args);
  const d = compareRgba(Uint8Array.from(frame.rgba), reference.rgba);
  assert.equal(d.max, 0, `${args.join(' ')}: ${d.differing} pixels differ, by up to ${d.max}`);

  if (process.env.MOIRE_SCREENSHOT) await page.screenshot({ path: process.env.MOIRE_SCREENSHOT });

  // Each back to the scene's own value.
  before = frame.id;
  for (const name of ['bold', 'ink']) await page.click(`.param[data-param=${name}] button.reset`);
  await page.waitForFunction(
    () => window.moire.state.params.every((p) => p.name === 'gap' || !p.set),
    { timeout: 30000 }
  );
  // The state can come before the answer to the reset; the page moves its controls once the
  // answer is in, so the test waits for them rather than reading them at once.
  await page
    .waitForFunction(
      () =>
        document.querySelector('input[type=checkbox][data-param=bold]').checked === false &&
        document.querySelector('input[type=color][data-param=ink]').value === '#141418',
      { timeout: 10000 }
    )
    .catch(() => {});
  assert.equal(await page.$eval('input[type=checkbox][data-param=bold]', (e) => e.checked), false);
  assert.equal(await page.$eval('input[type=color][data-param=ink]', (e) => e.value), '#141418');
});

test('the view toggles draw what moire render --view and --overlay draw', async () => {
  await page.waitForFunction(
    () => window.moire.state.params.every((p) => p.name === 'gap' || !p.set),
    { timeout: 30000 }
  );
  // The slider's value stays: the reference is rendered with it.
  const gap = await page.evaluate(() => window.moire.state.params.find((p) => p.name === 'gap').value[0]);
  for (const [click, args, view, overlay] of [
    ['#view-modes input[value=envelope]', ['--view', 'envelope'], 'envelope', null],
    ['#overlay', ['--view', 'envelope', '--overlay'], 'envelope', true],
    ['#view-modes input[value=scene]', ['--overlay'], 'scene', true],
  ]) {
    // The frame of everything before settled first: the next new frame is the click's.
    const before = (await shownFrame()).id;
    await page.click(click);
    await page.waitForFunction(
      (view, overlay) => window.moire.state.view === view && window.moire.state.overlay === overlay,
      { timeout: 30000 },
      view,
      overlay
    );
    const frame = await shownFrame(before);
    const reference = render(scenePath, frame.width, frame.height, [...args, '-D', `gap=${gap}`]);
    const d = compareRgba(Uint8Array.from(frame.rgba), reference.rgba);
    assert.equal(d.max, 0, `${args.join(' ')}: ${d.differing} pixels differ, by up to ${d.max}`);
  }
  await page.click('#overlay'); // off again
  await page.waitForFunction(() => window.moire.state.overlay === false, { timeout: 30000 });
});

test('zooming with the wheel draws what the server renders for the new view', async () => {
  const before = (await shownFrame()).id;
  const box = await page.$('#picture');
  const r = await box.boundingBox();
  await page.mouse.move(r.x + r.width / 2, r.y + r.height / 2);
  await page.mouse.wheel({ deltaY: -200 });
  await page.waitForFunction(() => window.moire.state.zoom > 1.15, { timeout: 30000 });
  const zoomed = await shownFrame(before);
  const state = await page.evaluate(() => window.moire.state);
  assert.ok(state.zoom > 1.15, `zoom ${state.zoom}`);
  // The server's frame is the one on the canvas, byte for byte.
  const response = await request(server, `/frame/${zoomed.id}.png`);
  assert.equal(response.status, 200);
  const png = decodePng(Buffer.from(await response.arrayBuffer()));
  assert.equal(compareRgba(Uint8Array.from(zoomed.rgba), png.rgba).max, 0);
  await page.click('#reset-view');
  await page.waitForFunction(() => window.moire.state.zoom === 1, { timeout: 30000 });
});
