// The settings as VS Code hands them over, and what is done with unusable ones.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { readSettings } from '../out/settings.js';
import { here } from './support.mjs';

const getter = (values) => (key) => values[key];

test('defaults: nothing set', () => {
  const { settings, problems } = readSettings(getter({}));
  assert.deepEqual(settings, {
    path: '',
    serverEnabled: true,
    renderOutput: '',
    renderSize: '',
    backend: '',
    previewSaveAfterPause: 0,
  });
  assert.deepEqual(problems, []);
});

test('values are read and trimmed', () => {
  const { settings, problems } = readSettings(
    getter({
      path: ' /opt/moire ',
      'server.enabled': false,
      'render.output': 'out/${stem}.tif',
      'render.size': '1920x1080',
      backend: 'interp',
      'preview.saveAfterPause': 400,
    }),
  );
  assert.deepEqual(settings, {
    path: '/opt/moire',
    serverEnabled: false,
    renderOutput: 'out/${stem}.tif',
    renderSize: '1920x1080',
    backend: 'interp',
    previewSaveAfterPause: 400,
  });
  assert.deepEqual(problems, []);
});

test('an unusable size or backend is left out, with a reason', () => {
  const { settings, problems } = readSettings(getter({ 'render.size': '1920 by 1080', backend: 'cuda' }));
  assert.equal(settings.renderSize, '');
  assert.equal(settings.backend, '');
  assert.equal(problems.length, 2);
  assert.match(problems[0], /WIDTHxHEIGHT/);
  assert.match(problems[1], /jit, interp or vulkan/);
});

test('a pause that is not a whole number of milliseconds up to a minute is left out, with a reason', () => {
  for (const pause of [-1, 1.5, 60001, '300']) {
    const { settings, problems } = readSettings(getter({ 'preview.saveAfterPause': pause }));
    assert.equal(settings.previewSaveAfterPause, 0);
    assert.equal(problems.length, 1);
    assert.match(problems[0], /moire\.preview\.saveAfterPause.*0 to 60000/);
  }
});

test('every setting the manifest declares is one the extension reads, and no other', () => {
  const manifest = JSON.parse(readFileSync(join(here, '..', 'package.json'), 'utf8'));
  const declared = Object.keys(manifest.contributes.configuration.properties).map((k) => k.replace(/^moire\./, ''));
  const read = [];
  readSettings((key) => {
    read.push(key);
    return undefined;
  });
  assert.deepEqual([...read].sort(), [...declared].sort());
});
