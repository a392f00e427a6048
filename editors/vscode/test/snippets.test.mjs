// Each snippet that writes a declaration, expanded with its placeholders' defaults, is a scene
// the real moire checks without an error: a snippet never teaches a syntax the language lost.
import assert from 'node:assert/strict';
import { execFileSync, spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { moire, sourceRoot } from './support.mjs';

const snippets = JSON.parse(readFileSync(join(sourceRoot, 'editors/vscode/snippets/moire.json'), 'utf8'));
const keywords = JSON.parse(execFileSync(moire, ['names', '--json'], { encoding: 'utf8' })).keywords;

// The text VS Code inserts when every placeholder keeps its default.
const expand = (body) =>
  body.join('\n').replace(/\$\{\d+:([^}]*)\}/g, '$1').replace(/\$\d+/g, '').replace(/\t/g, '    ');

test('every declaration snippet, expanded, is a scene moire check accepts', () => {
  const checked = [];
  for (const [name, s] of Object.entries(snippets)) {
    const text = expand(s.body);
    if (!keywords.includes(text.split(/[\s({]/)[0])) continue;
    const r = spawnSync(moire, ['check', '-'], { input: text, encoding: 'utf8' });
    assert.equal(r.status, 0, `the snippet '${name}' gives:\n${text}\n${r.stderr}`);
    checked.push(name);
  }
  assert.ok(checked.includes('param') && checked.includes('layer'), checked.join());
});
