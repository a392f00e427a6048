// "moire: Open Preview": `moire serve` started for a scene, and the webview that shows its
// page. No `vscode` import: extension.ts shows what these make, and node's test runner runs
// them against the real binary. The page itself is moire's (runtime/serve/page/): one page,
// in the browser and here.
import { ChildProcess, spawn } from 'node:child_process';
import { dirname } from 'node:path';
import { createInterface } from 'node:readline';
import type { CommandLine } from './commands';
import type { MoireSettings } from './settings';

export function serveCommandLine(
  moire: string,
  scene: string,
  settings: Pick<MoireSettings, 'backend'>,
): CommandLine {
  const args = ['serve', scene, '--port', '0'];
  if (settings.backend) args.push('--backend', settings.backend);
  return { command: moire, args, cwd: dirname(scene) };
}

export interface ServeProcess {
  url: string; // the page's address, with the run's token
  child: ChildProcess;
  // Stops the server; resolves with its exit status (0 when it stopped as asked).
  stop(): Promise<number | null>;
}

// Starts `moire serve` and resolves once it printed the page's address (its first line on
// standard output). What it prints on standard error goes to `log`. Rejects, with what it
// said, when it exits first or says nothing within `timeoutMs`.
export function startServe(
  line: CommandLine,
  log: (text: string) => void = () => {},
  timeoutMs = 30000,
): Promise<ServeProcess> {
  return new Promise((resolvePromise, reject) => {
    const child = spawn(line.command, line.args, { cwd: line.cwd, stdio: ['ignore', 'pipe', 'pipe'] });
    let said = '';
    child.stderr.setEncoding('utf8').on('data', (d: string) => {
      said += d;
      log(d);
    });
    const fail = (why: string) => {
      clearTimeout(timer);
      child.kill('SIGTERM');
      reject(new Error(said ? `${why}\n${said.trim()}` : why));
    };
    const timer = setTimeout(() => fail(`moire serve printed no address in ${timeoutMs / 1000} s`), timeoutMs);
    child.on('error', (e) => fail(`cannot run ${line.command}: ${e.message}`));
    const exited = (code: number | null) => fail(`moire serve exited with status ${code}`);
    child.once('exit', exited);
    createInterface({ input: child.stdout }).once('line', (url) => {
      clearTimeout(timer);
      child.off('exit', exited);
      if (!/^https?:\/\/[^ ]+\?token=[0-9a-f]+$/.test(url)) return fail(`moire serve printed '${url}', not an address`);
      const exit = new Promise<number | null>((done) => {
        if (child.exitCode !== null) done(child.exitCode);
        else child.once('exit', (code) => done(code));
      });
      resolvePromise({
        url,
        child,
        stop: () => {
          if (child.exitCode === null) child.kill('SIGTERM');
          return exit;
        },
      });
    });
  });
}

function escapeAttribute(s: string): string {
  return s.replace(/&/g, '&amp;').replace(/"/g, '&quot;').replace(/</g, '&lt;').replace(/>/g, '&gt;');
}

// The webview's HTML: the page in a frame filling the view. `url` is the address as the
// webview can reach it (vscode.env.asExternalUri of the printed one, for remote windows).
export function previewHtml(url: string, title: string): string {
  const origin = new URL(url).origin;
  return `<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; frame-src ${escapeAttribute(origin)}; style-src 'unsafe-inline'">
<title>${escapeAttribute(title)}</title>
<style>html, body, iframe { margin: 0; padding: 0; border: 0; width: 100%; height: 100%; overflow: hidden; display: block; }</style>
</head>
<body><iframe src="${escapeAttribute(url)}" title="${escapeAttribute(title)}" referrerpolicy="no-referrer"></iframe></body>
</html>
`;
}
