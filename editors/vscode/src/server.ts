// Starting the language server: `moire lsp`, speaking LSP over its standard input and
// output. No `vscode` import; extension.ts hands this to vscode-languageclient.
import { execFileSync } from 'node:child_process';

export const serverArgs = ['lsp'];

export function serverCommand(moire: string): { command: string; args: string[] } {
  return { command: moire, args: [...serverArgs] };
}

// Whether `moire` has the subcommand `name`: its --help lists the subcommands, one a line,
// indented under "Subcommands:" up to the next blank line. A moire built before the server existed has no `lsp`; the
// extension then still highlights and runs the commands, and says why there are no
// diagnostics.
export function hasSubcommand(moire: string, name: string): boolean {
  let help: string;
  try {
    help = execFileSync(moire, ['--help'], { encoding: 'utf8', stdio: ['ignore', 'pipe', 'ignore'] });
  } catch {
    return false;
  }
  const section = (help.split(/^Subcommands:\s*$/im)[1] ?? '').split(/\n\s*\n/)[0];
  return section.split('\n').some((line) => line.trim().split(/\s+/)[0] === name);
}
