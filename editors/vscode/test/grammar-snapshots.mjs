#!/usr/bin/env node
// Snapshot tests of the TextMate grammar over every example (vscode-tmgrammar-test): each
// examples/NAME.moire has test/grammar/NAME.moire.snap, the scopes of each of its tokens.
// The tool keeps a snapshot beside its file, so the examples are copied with their
// snapshots into a scratch folder and checked there; a change of the grammar that changes
// what an example looks like shows as a diff.
//
//   node test/grammar-snapshots.mjs            check (ctest runs this)
//   node test/grammar-snapshots.mjs --update   write the snapshots anew, after a grammar change
import { spawnSync } from 'node:child_process';
import { copyFileSync, existsSync, mkdtempSync, readdirSync, rmSync, unlinkSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const vscodeDir = resolve(fileURLToPath(import.meta.url), '../..');
const examples = resolve(vscodeDir, '../../examples');
const snapshots = join(vscodeDir, 'test/grammar');
const update = process.argv.includes('--update');

const scenes = readdirSync(examples).filter((f) => f.endsWith('.moire')).sort();
const problems = [];
for (const snap of readdirSync(snapshots).filter((f) => f.endsWith('.snap'))) {
  if (scenes.includes(snap.replace(/\.snap$/, ''))) continue;
  if (update) unlinkSync(join(snapshots, snap));
  else problems.push(`test/grammar/${snap} is the snapshot of no example (remove it, or run --update)`);
}

const work = mkdtempSync(join(tmpdir(), 'moire-grammar-'));
try {
  for (const scene of scenes) {
    copyFileSync(join(examples, scene), join(work, scene));
    const snap = join(snapshots, `${scene}.snap`);
    if (existsSync(snap)) copyFileSync(snap, join(work, `${scene}.snap`));
    else if (!update) problems.push(`examples/${scene} has no snapshot test/grammar/${scene}.snap (run --update)`);
  }
  const tool = join(vscodeDir, 'node_modules/.bin/vscode-tmgrammar-snap');
  const args = ['--scope', 'source.moire', '--grammar', 'syntaxes/moire.tmLanguage.json', `${work}/*.moire`];
  if (update) args.unshift('--updateSnapshot');
  const run = spawnSync(tool, args, { cwd: vscodeDir, encoding: 'utf8' });
  process.stdout.write(run.stdout);
  process.stderr.write(run.stderr);
  if (run.status !== 0) problems.push(`vscode-tmgrammar-snap exited with ${run.status}`);
  if (update) for (const scene of scenes) copyFileSync(join(work, `${scene}.snap`), join(snapshots, `${scene}.snap`));
} finally {
  rmSync(work, { recursive: true, force: true });
}
for (const p of problems) console.error(`grammar-snapshots: ${p}`);
console.log(
  problems.length ? 'grammar-snapshots: FAILED' : `grammar-snapshots: ${scenes.length} examples ${update ? 'written' : 'as their snapshots'}`,
);
process.exit(problems.length ? 1 : 0);
