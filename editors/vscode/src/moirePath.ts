// Which `moire` program the extension runs: the setting `moire.path` when it is set, else
// `moire` on PATH. No `vscode` import, so that node's test runner can test it on its own.
import { accessSync, constants, statSync } from 'node:fs';
import { delimiter, isAbsolute, join, resolve } from 'node:path';

export interface ResolveInput {
  setting: string; // moire.path: '' for the default
  env: NodeJS.ProcessEnv; // PATH is read from it
  workspaceFolder?: string; // what a relative path in the setting is relative to
  home?: string; // what ~ stands for
}

export type Resolved = { path: string } | { error: string };

function isExecutableFile(p: string): boolean {
  try {
    if (!statSync(p).isFile()) return false;
    accessSync(p, constants.X_OK);
    return true;
  } catch {
    return false;
  }
}

// The first executable `name` in the directories of PATH.
export function searchPath(name: string, env: NodeJS.ProcessEnv): string | undefined {
  for (const dir of (env.PATH ?? '').split(delimiter)) {
    if (dir === '') continue;
    const candidate = join(dir, name);
    if (isExecutableFile(candidate)) return candidate;
  }
  return undefined;
}

export function resolveMoire(input: ResolveInput): Resolved {
  const setting = input.setting.trim();
  if (setting === '') {
    const found = searchPath('moire', input.env);
    return found
      ? { path: found }
      : { error: 'moire was not found on PATH: install it, or set moire.path to the moire program' };
  }
  // A bare name is looked up on PATH, as a shell would; anything with a slash is a file.
  if (!setting.includes('/') && !setting.startsWith('~')) {
    const found = searchPath(setting, input.env);
    return found
      ? { path: found }
      : { error: `moire.path is '${setting}', which is not a program on PATH` };
  }
  let p = setting;
  if (p === '~' || p.startsWith('~/')) {
    if (!input.home) return { error: `moire.path is '${setting}', but there is no home directory to expand ~` };
    p = join(input.home, p.slice(1));
  }
  if (!isAbsolute(p)) {
    if (!input.workspaceFolder)
      return { error: `moire.path is the relative path '${setting}', but no folder is open to be relative to` };
    p = resolve(input.workspaceFolder, p);
  }
  return isExecutableFile(p)
    ? { path: p }
    : { error: `moire.path is '${setting}', which is not an executable file (${p})` };
}
