// Which moire the extension runs: moire.path, else moire on PATH.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { chmodSync, copyFileSync, mkdirSync, symlinkSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { resolveMoire, searchPath } from '../out/moirePath.js';
import { moire, scratch } from './support.mjs';

// A folder holding a link to the real moire, as an install on PATH would.
function binDir(t) {
  const dir = join(scratch(t), 'bin');
  mkdirSync(dir);
  symlinkSync(moire, join(dir, 'moire'));
  return dir;
}

test('no setting: moire on PATH, and the program found runs', (t) => {
  const bin = binDir(t);
  const r = resolveMoire({ setting: '', env: { PATH: `/nonexistent:${bin}` } });
  assert.deepEqual(r, { path: join(bin, 'moire') });
  assert.match(execFileSync(r.path, ['--version'], { encoding: 'utf8' }), /\d+\.\d+/);
});

test('no setting and no moire on PATH: an error that says what to do', () => {
  const r = resolveMoire({ setting: '', env: { PATH: '/nonexistent' } });
  assert.match(r.error, /not found on PATH.*moire\.path/);
});

test('a path in the setting, absolute, relative to the folder, or under ~', (t) => {
  const bin = binDir(t);
  const root = join(bin, '..');
  assert.deepEqual(resolveMoire({ setting: moire, env: {} }), { path: moire });
  assert.deepEqual(resolveMoire({ setting: 'bin/moire', env: {}, workspaceFolder: root }), {
    path: join(bin, 'moire'),
  });
  assert.deepEqual(resolveMoire({ setting: '~/bin/moire', env: {}, home: root }), { path: join(bin, 'moire') });
  assert.match(resolveMoire({ setting: 'bin/moire', env: {} }).error, /no folder is open/);
});

test('a bare name in the setting is looked up on PATH', (t) => {
  const bin = binDir(t);
  symlinkSync(moire, join(bin, 'moire-dev'));
  assert.deepEqual(resolveMoire({ setting: 'moire-dev', env: { PATH: bin } }), { path: join(bin, 'moire-dev') });
  assert.match(resolveMoire({ setting: 'moire-nope', env: { PATH: bin } }).error, /not a program on PATH/);
});

test('a setting that names no executable file is refused', (t) => {
  const dir = scratch(t);
  const text = join(dir, 'moire');
  writeFileSync(text, 'not a program');
  assert.match(resolveMoire({ setting: text, env: {} }).error, /not an executable file/);
  assert.match(resolveMoire({ setting: dir, env: {} }).error, /not an executable file/); // a folder
  // PATH skips what it cannot run, as a shell does.
  const other = join(dir, 'other');
  mkdirSync(other);
  copyFileSync(text, join(other, 'moire'));
  chmodSync(join(other, 'moire'), 0o644);
  assert.equal(searchPath('moire', { PATH: other }), undefined);
});
