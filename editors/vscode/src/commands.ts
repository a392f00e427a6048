// The command lines of "moire: Render Current File" and "moire: Open Viewer", and running
// them. No `vscode` import: the extension shows what these return.
import { spawn } from 'node:child_process';
import { basename, dirname, extname, isAbsolute, join } from 'node:path';
import type { MoireSettings } from './settings';

export interface CommandLine {
  command: string;
  args: string[];
  cwd: string; // the scene's folder
}

// The image a render writes: moire.render.output with ${stem} replaced, relative to the
// scene's folder; by default <stem>.png beside the scene.
export function renderOutput(scene: string, settings: Pick<MoireSettings, 'renderOutput'>): string {
  const stem = basename(scene, extname(scene));
  const name = (settings.renderOutput || '${stem}.png').split('${stem}').join(stem);
  return isAbsolute(name) ? name : join(dirname(scene), name);
}

function backendArgs(settings: Pick<MoireSettings, 'backend'>): string[] {
  return settings.backend ? ['--backend', settings.backend] : [];
}

export function renderCommandLine(
  moire: string,
  scene: string,
  settings: Pick<MoireSettings, 'renderOutput' | 'renderSize' | 'backend'>,
): CommandLine & { output: string } {
  const output = renderOutput(scene, settings);
  const args = ['render', scene, '-o', output];
  if (settings.renderSize) args.push('--size', settings.renderSize);
  args.push(...backendArgs(settings));
  return { command: moire, args, cwd: dirname(scene), output };
}

export function viewCommandLine(
  moire: string,
  scene: string,
  settings: Pick<MoireSettings, 'backend'>,
): CommandLine {
  return { command: moire, args: ['view', scene, ...backendArgs(settings)], cwd: dirname(scene) };
}

export interface RunResult {
  code: number | null; // null: ended by a signal
  stdout: string;
  stderr: string;
}

// Runs a command line to its end, collecting what it prints (moire's diagnostics go to
// standard error as file:line:col: error: message).
export function run(line: CommandLine): Promise<RunResult> {
  return new Promise((resolvePromise, reject) => {
    const child = spawn(line.command, line.args, { cwd: line.cwd, stdio: ['ignore', 'pipe', 'pipe'] });
    let stdout = '';
    let stderr = '';
    child.stdout.setEncoding('utf8').on('data', (d: string) => (stdout += d));
    child.stderr.setEncoding('utf8').on('data', (d: string) => (stderr += d));
    child.on('error', reject);
    child.on('close', (code) => resolvePromise({ code, stdout, stderr }));
  });
}
