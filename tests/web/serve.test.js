// `moire serve` in a real browser: the page shows what `moire render` draws, follows saves
// (a bad one shows its located diagnostic over the last picture; the fix brings a picture
// back), and the server refuses requests without the run's token.
//
// MOIRE_SCREENSHOT=path.png also saves a screenshot of the page (docs/images/serve.png).
'use strict';
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
const { compareRgba } = require('./png.js');
const { tempDir, startServe, request, json, waitFor, render, launchBrowser } = require('./serve_support.js');

const scene = (spacing) => `scene {
    size = (640, 400)
    background = #f6f3ec
}

layer left {
    family = circles
    spacing = ${spacing}
    stroke = 1.8
    color = #141418
    origin = (-30, 0)
}

layer right {
    family = circles
    spacing = ${spacing}
    stroke = 1.8
    color = #141418
    origin = (30, 0)
}
`;
// Line 8 is `spacing = ;`: the diagnostic points at line 8.
const broken = scene('').replace('spacing = \n', 'spacing = ;\n');

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
  assert.match(text, /rings\.moire:8:15: error: /);
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

  if (process.env.MOIRE_SCREENSHOT) await page.screenshot({ path: process.env.MOIRE_SCREENSHOT });
});

test('zooming with the wheel draws what the server renders for the new view', async () => {
  const before = await page.evaluate(() => window.moire.shown.id);
  const box = await page.$('#picture');
  const r = await box.boundingBox();
  await page.mouse.move(r.x + r.width / 2, r.y + r.height / 2);
  await page.mouse.wheel({ deltaY: -200 });
  const zoomed = await shownFrame(before);
  const state = await page.evaluate(() => window.moire.state);
  assert.ok(state.zoom > 1.15, `zoom ${state.zoom}`);
  // The server's frame is the one on the canvas, byte for byte.
  const response = await request(server, `/frame/${zoomed.id}.png`);
  assert.equal(response.status, 200);
  const { decodePng } = require('./png.js');
  const png = decodePng(Buffer.from(await response.arrayBuffer()));
  assert.equal(compareRgba(Uint8Array.from(zoomed.rgba), png.rgba).max, 0);
  await page.click('#reset-view');
  await page.waitForFunction(() => window.moire.state.zoom === 1, { timeout: 30000 });
});
