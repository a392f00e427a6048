// What the extension's tests share: the real moire binary (MOIRE_BINARY, else the
// build's), and a scratch folder.
import { existsSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

export const here = dirname(fileURLToPath(import.meta.url));
export const sourceRoot = resolve(here, '../../..');
export const moire = process.env.MOIRE_BINARY ?? join(sourceRoot, 'build/bin/moire');
if (!existsSync(moire)) throw new Error(`no moire binary at ${moire}: build it, or set MOIRE_BINARY`);

export function scratch(t) {
  const dir = mkdtempSync(join(tmpdir(), 'moire-vscode-'));
  t.after(() => rmSync(dir, { recursive: true, force: true }));
  return dir;
}
