// The VS Code side: the language server through vscode-languageclient, and the render,
// viewer and preview commands. What can be decided without VS Code (which moire, its command lines,
// the settings) lives in the modules beside this one, which node's test runner tests.
import * as vscode from 'vscode';
import { LanguageClient, LanguageClientOptions, ServerOptions, TransportKind } from 'vscode-languageclient/node';
import { CommandLine, renderCommandLine, run, viewCommandLine } from './commands';
import { previewHtml, serveCommandLine, ServeProcess, startServe } from './preview';
import { resolveMoire } from './moirePath';
import { hasSubcommand, serverCommand } from './server';
import { MoireSettings, readSettings } from './settings';
import { spawn } from 'node:child_process';
import { homedir } from 'node:os';
import { basename } from 'node:path';

let client: LanguageClient | undefined;
let output: vscode.OutputChannel;

function settings(): MoireSettings {
  const config = vscode.workspace.getConfiguration('moire');
  const { settings: s, problems } = readSettings((key) => config.get(key));
  for (const p of problems) output.appendLine(`moire: ${p}`);
  return s;
}

// The moire program, or undefined after saying why there is none.
function moireProgram(s: MoireSettings, quiet = false): string | undefined {
  const r = resolveMoire({
    setting: s.path,
    env: process.env,
    workspaceFolder: vscode.workspace.workspaceFolders?.[0]?.uri.fsPath,
    home: homedir(),
  });
  if ('path' in r) return r.path;
  output.appendLine(`moire: ${r.error}`);
  if (!quiet) void vscode.window.showErrorMessage(r.error);
  return undefined;
}

async function startServer(): Promise<void> {
  const s = settings();
  if (!s.serverEnabled) return;
  const moire = moireProgram(s, true);
  if (!moire) return;
  if (!hasSubcommand(moire, 'lsp')) {
    output.appendLine(`moire: ${moire} has no language server (moire lsp); highlighting and the commands still work`);
    return;
  }
  const server = serverCommand(moire);
  const serverOptions: ServerOptions = { command: server.command, args: server.args, transport: TransportKind.stdio };
  const clientOptions: LanguageClientOptions = {
    documentSelector: [
      { scheme: 'file', language: 'moire' },
      { scheme: 'untitled', language: 'moire' },
    ],
    outputChannel: output,
  };
  client = new LanguageClient('moire', 'moire language server', serverOptions, clientOptions);
  await client.start();
}

async function stopServer(): Promise<void> {
  const c = client;
  client = undefined;
  if (c) await c.stop();
}

// The scene in the active editor, saved, or undefined after saying why there is none.
async function activeScene(): Promise<string | undefined> {
  const doc = vscode.window.activeTextEditor?.document;
  if (!doc || doc.languageId !== 'moire') {
    void vscode.window.showErrorMessage('moire: open a .moire scene first');
    return undefined;
  }
  if (doc.isUntitled || doc.uri.scheme !== 'file') {
    void vscode.window.showErrorMessage('moire: save the scene to a file first');
    return undefined;
  }
  if (doc.isDirty && !(await doc.save())) return undefined;
  return doc.uri.fsPath;
}

// The active scene, the moire to run on it and the settings, or undefined after saying why not.
async function sceneToRun(): Promise<{ scene: string; moire: string; s: MoireSettings } | undefined> {
  const scene = await activeScene();
  const s = settings();
  const moire = scene && moireProgram(s);
  return scene && moire ? { scene, moire, s } : undefined;
}

function echo(line: CommandLine): void {
  output.appendLine(`$ ${line.command} ${line.args.join(' ')}`);
}

async function renderCurrentFile(): Promise<void> {
  const target = await sceneToRun();
  if (!target) return;
  const line = renderCommandLine(target.moire, target.scene, target.s);
  echo(line);
  const result = await vscode.window.withProgress(
    { location: vscode.ProgressLocation.Window, title: 'moire: rendering' },
    () => run(line),
  );
  if (result.stdout) output.append(result.stdout);
  if (result.stderr) output.append(result.stderr);
  if (result.code === 0) {
    const choice = await vscode.window.showInformationMessage(`moire: wrote ${line.output}`, 'Open');
    if (choice === 'Open') await vscode.commands.executeCommand('vscode.open', vscode.Uri.file(line.output));
  } else {
    output.show(true);
    void vscode.window.showErrorMessage(`moire render failed (exit status ${result.code}); see the moire output`);
  }
}

async function openViewer(): Promise<void> {
  const target = await sceneToRun();
  if (!target) return;
  // The viewer reloads the scene on every save, so it is started once and left running.
  const line = viewCommandLine(target.moire, target.scene, target.s);
  echo(line);
  const child = spawn(line.command, line.args, { cwd: line.cwd, stdio: ['ignore', 'pipe', 'pipe'] });
  child.stdout.setEncoding('utf8').on('data', (d: string) => output.append(d));
  child.stderr.setEncoding('utf8').on('data', (d: string) => output.append(d));
  child.on('error', (e) => void vscode.window.showErrorMessage(`moire view: ${e.message}`));
  child.on('close', (code) => {
    if (code !== 0 && code !== null) {
      output.show(true);
      void vscode.window.showErrorMessage(`moire view exited with status ${code}; see the moire output`);
    }
  });
}

// One preview per scene: its panel and the `moire serve` behind it. The server follows the
// file, so a save updates the page without a word from here.
const previews = new Map<string, { panel: vscode.WebviewPanel; server: ServeProcess }>();

async function openPreview(): Promise<void> {
  const target = await sceneToRun();
  if (!target) return;
  const open = previews.get(target.scene);
  if (open) {
    open.panel.reveal(vscode.ViewColumn.Beside, true);
    return;
  }
  const line = serveCommandLine(target.moire, target.scene, target.s);
  echo(line);
  let server: ServeProcess;
  try {
    server = await vscode.window.withProgress(
      { location: vscode.ProgressLocation.Window, title: 'moire: starting the preview' },
      () => startServe(line, (text) => output.append(text)),
    );
  } catch (e) {
    output.show(true);
    void vscode.window.showErrorMessage(`moire serve: ${(e as Error).message.split('\n')[0]}; see the moire output`);
    return;
  }
  // In a remote window the address is forwarded; locally it is the same.
  const external = await vscode.env.asExternalUri(vscode.Uri.parse(server.url));
  const title = `Preview ${basename(target.scene)}`;
  const panel = vscode.window.createWebviewPanel(
    'moire.preview',
    title,
    { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
    { enableScripts: true, retainContextWhenHidden: true },
  );
  panel.webview.html = previewHtml(external.toString(true), title);
  previews.set(target.scene, { panel, server });
  panel.onDidDispose(() => {
    previews.delete(target.scene);
    void server.stop();
  });
  server.child.on('exit', (code) => {
    if (previews.get(target.scene)?.server !== server) return;
    output.appendLine(`moire serve for ${target.scene} exited with status ${code}`);
    panel.dispose();
  });
}

// moire.preview.saveAfterPause: a scene with an open preview is saved once typing pauses, and
// the server, which follows the file, draws it.
const pauseTimers = new Map<string, NodeJS.Timeout>();

function saveAfterPause(doc: vscode.TextDocument): void {
  if (doc.uri.scheme !== 'file' || !previews.has(doc.uri.fsPath)) return;
  const pause = settings().previewSaveAfterPause;
  if (pause <= 0) return;
  clearTimeout(pauseTimers.get(doc.uri.fsPath));
  pauseTimers.set(
    doc.uri.fsPath,
    setTimeout(() => {
      pauseTimers.delete(doc.uri.fsPath);
      if (doc.isDirty && !doc.isClosed) void doc.save();
    }, pause),
  );
}

export async function activate(context: vscode.ExtensionContext): Promise<void> {
  output = vscode.window.createOutputChannel('moire');
  context.subscriptions.push(
    output,
    vscode.commands.registerCommand('moire.render', renderCurrentFile),
    vscode.commands.registerCommand('moire.view', openViewer),
    vscode.commands.registerCommand('moire.preview', openPreview),
    vscode.commands.registerCommand('moire.restartServer', async () => {
      await stopServer();
      await startServer();
    }),
    vscode.workspace.onDidChangeTextDocument((e) => saveAfterPause(e.document)),
    vscode.workspace.onDidChangeConfiguration(async (e) => {
      if (e.affectsConfiguration('moire.path') || e.affectsConfiguration('moire.server')) {
        await stopServer();
        await startServer();
      }
    }),
  );
  await startServer();
}

export async function deactivate(): Promise<void> {
  await Promise.all([...previews.values()].map((p) => p.server.stop()));
  await stopServer();
}
