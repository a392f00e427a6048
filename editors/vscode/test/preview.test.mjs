// "moire: Open Preview": moire serve started for a scene, its page reachable at the address it
// printed (and not without the token), and the webview's frame pointing there.
import assert from 'node:assert/strict';
import { copyFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { previewHtml, serveCommandLine, startServe } from '../out/preview.js';
import { moire, scratch, sourceRoot } from './support.mjs';

test('the serve command line: any free port, the backend setting', () => {
  assert.deepEqual(serveCommandLine('moire', '/w/a b.moire', { backend: '' }), {
    command: 'moire',
    args: ['serve', '/w/a b.moire', '--port', '0'],
    cwd: '/w',
  });
  assert.deepEqual(serveCommandLine('moire', '/w/s.moire', { backend: 'vulkan' }).args, [
    'serve', '/w/s.moire', '--port', '0', '--backend', 'vulkan',
  ]);
});

test('moire serve starts, its page answers with the token only, and stops when asked', async (t) => {
  const dir = scratch(t);
  const scene = join(dir, 'two rings.moire');
  copyFileSync(join(sourceRoot, 'examples/two_rings.moire'), scene);
  const server = await startServe(serveCommandLine(moire, scene, { backend: '' }));
  t.after(() => server.stop());
  const url = new URL(server.url);
  assert.equal(url.hostname, '127.0.0.1');
  const page = await fetch(server.url);
  assert.equal(page.status, 200);
  assert.match(await page.text(), /<canvas id="picture"/);
  const refused = await fetch(url.origin + '/');
  assert.equal(refused.status, 403);
  await refused.text();
  assert.equal(await server.stop(), 0);
});

test('a scene that cannot be served is a rejection with what moire said', async (t) => {
  const dir = scratch(t);
  const scene = join(dir, 's.moire');
  writeFileSync(scene, 'layer { family = circles }\n');
  await assert.rejects(
    startServe(serveCommandLine(moire, scene, { backend: 'nonesuch' })),
    /exited with status 2[\s\S]*nonesuch/,
  );
  await assert.rejects(startServe(serveCommandLine(join(dir, 'no-moire'), scene, { backend: '' })), /cannot run/);
});

test('the webview frames the page, and allows that origin only', () => {
  const html = previewHtml('http://127.0.0.1:4321/?token=abc', 'rings.moire "preview"');
  assert.match(html, /<iframe src="http:\/\/127\.0\.0\.1:4321\/\?token=abc"/);
  assert.match(html, /frame-src http:\/\/127\.0\.0\.1:4321;/);
  assert.match(html, /default-src 'none'/);
  assert.match(html, /rings\.moire &quot;preview&quot;/);
});
