// "moire: Render Current File" and "moire: Open Viewer": their command lines, run with the
// real moire binary.
import assert from 'node:assert/strict';
import { copyFileSync, existsSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { renderCommandLine, renderOutput, run, viewCommandLine } from '../out/commands.js';
import { moire, scratch, sourceRoot } from './support.mjs';

const PNG = Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]);
const defaults = { renderOutput: '', renderSize: '', backend: '' };

test('the rendered image: beside the scene by default, or as moire.render.output says', () => {
  assert.equal(renderOutput('/w/scenes/rings.moire', defaults), '/w/scenes/rings.png');
  assert.equal(renderOutput('/w/scenes/rings.moire', { renderOutput: 'out/${stem}-big.tif' }), '/w/scenes/out/rings-big.tif');
  assert.equal(renderOutput('/w/scenes/rings.moire', { renderOutput: '/tmp/${stem}.exr' }), '/tmp/rings.exr');
});

test('render: the command line renders the scene to the image, at the size asked', async (t) => {
  const dir = scratch(t);
  const scene = join(dir, 'two rings.moire'); // a space: the arguments are never a shell line
  copyFileSync(join(sourceRoot, 'examples/two_rings.moire'), scene);
  const line = renderCommandLine(moire, scene, { ...defaults, renderSize: '64x40', backend: 'interp' });
  assert.deepEqual(line.args, ['render', scene, '-o', join(dir, 'two rings.png'), '--size', '64x40', '--backend', 'interp']);
  assert.equal(line.cwd, dir);
  const result = await run(line);
  assert.equal(result.code, 0, result.stderr);
  const png = readFileSync(line.output);
  assert.deepEqual(png.subarray(0, 8), PNG);
  assert.equal(png.readUInt32BE(16), 64); // IHDR: width, height
  assert.equal(png.readUInt32BE(20), 40);
});

test('render: a scene with errors gives moire check\'s diagnostics and no image', async (t) => {
  const dir = scratch(t);
  const scene = join(dir, 'bad.moire');
  writeFileSync(scene, 'layer { family = circls }\n');
  const line = renderCommandLine(moire, scene, defaults);
  const result = await run(line);
  assert.equal(result.code, 1);
  assert.match(result.stderr, /bad\.moire:1:18: error: unknown family 'circls'/);
  assert.equal(existsSync(line.output), false);
});

test('view: the command line is one the viewer takes', async (t) => {
  // No window here: a scene that cannot be read stops the viewer before it opens one, after
  // the command line was understood (a command line moire does not take is status 2).
  const dir = scratch(t);
  const scene = join(dir, 'missing.moire');
  const line = viewCommandLine(moire, scene, { backend: 'jit' });
  assert.deepEqual(line.args, ['view', scene, '--backend', 'jit']);
  assert.equal(line.cwd, dir);
  const result = await run(line);
  assert.notEqual(result.code, 0);
  assert.notEqual(result.code, 2, result.stderr);
  assert.match(result.stderr, /cannot read '.*missing\.moire'/);
  const usage = await run({ ...line, args: [...line.args, '--no-such-option'] });
  assert.equal(usage.code, 2);
});
