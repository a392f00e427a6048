// A scripted session with `moire lsp`, driven by the JSON-RPC and protocol libraries VS Code's
// own client is built on: what an editor sees, checked against `moire check --format=json`.
'use strict';
const { test } = require('node:test');
const assert = require('node:assert/strict');
const { spawn, execFileSync } = require('node:child_process');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { pathToFileURL } = require('node:url');
const rpc = require('vscode-jsonrpc/node');
const lsp = require('vscode-languageserver-protocol');

const moire = process.env.MOIRE_BINARY;
const sourceDir = process.env.MOIRE_SOURCE_DIR;

function start() {
  const proc = spawn(moire, ['lsp'], { stdio: ['pipe', 'pipe', 'inherit'] });
  const conn = rpc.createMessageConnection(
    new rpc.StreamMessageReader(proc.stdout), new rpc.StreamMessageWriter(proc.stdin));
  const published = [];
  const waiters = [];
  conn.onNotification(lsp.PublishDiagnosticsNotification.type, (p) => {
    published.push(p);
    for (const w of waiters.splice(0)) w();
  });
  conn.listen();
  const exited = new Promise((resolve) => proc.on('exit', (code) => resolve(code)));
  // The next diagnostics published for `uri` (and `version`, when given).
  async function diagnostics(uri, version) {
    for (;;) {
      const i = published.findIndex((p) => p.uri === uri && (version === undefined || p.version === version));
      if (i >= 0) return published.splice(0, i + 1).pop().diagnostics;
      await new Promise((resolve) => waiters.push(resolve));
    }
  }
  return { proc, conn, diagnostics, exited };
}

async function initialize(conn) {
  const init = await conn.sendRequest(lsp.InitializeRequest.type,
    { processId: process.pid, rootUri: null, capabilities: {} });
  await conn.sendNotification(lsp.InitializedNotification.type, {});
  return init;
}

async function shutDown(s) {
  await s.conn.sendRequest(lsp.ShutdownRequest.type);
  await s.conn.sendNotification(lsp.ExitNotification.type);
  assert.equal(await s.exited, 0);
  s.conn.dispose();
}

// `moire check --format=json`'s diagnostics of a file.
function check(file) {
  let out;
  try {
    out = execFileSync(moire, ['check', '--format=json', file], { encoding: 'utf8' });
  } catch (e) {
    out = e.stdout; // a scene with errors exits 1
  }
  return JSON.parse(out).scenes[0].diagnostics;
}

function sameAsCheck(got, want, file) {
  assert.equal(got.length, want.length, JSON.stringify(got));
  want.forEach((w, i) => {
    assert.equal(got[i].message, w.message);
    assert.equal(got[i].code, w.id);
    assert.equal(got[i].severity, w.severity === 'error' ? 1 : 3);
    if (w.range && w.range.file === file) {
      assert.deepEqual(got[i].range, {
        start: { line: w.range.start.line - 1, character: w.range.start.column - 1 },
        end: { line: w.range.end.line - 1, character: w.range.end.column - 1 },
      });
    }
  });
}

test('a session: diagnostics as moire check prints them, then hover, completion, definition', async (t) => {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'moire-lsp-'));
  const file = path.join(dir, 'scene.moire');
  // Two mistakes: a misspelt family (with a suggestion) and a property set twice (an error
  // and a note).
  const text = 'timing slow { period = 4 }\n' +
               'layer ring {\n' +
               '    family = circels\n' +
               '    spacing = ramp(slow, 8, 12)\n' +
               '    color = #223344\n' +
               '    spacing = 3\n' +
               '}\n';
  fs.writeFileSync(file, text);
  const uri = pathToFileURL(file).href;
  const s = start();
  t.after(() => s.proc.kill());
  const init = await initialize(s.conn);
  assert.equal(init.capabilities.hoverProvider, true);

  await s.conn.sendNotification(lsp.DidOpenTextDocumentNotification.type,
    { textDocument: { uri, languageId: 'moire', version: 1, text } });
  const opened = await s.diagnostics(uri, 1);
  assert.equal(opened.length, 3);
  sameAsCheck(opened, check(file), file);

  // The quick fix for the misspelling.
  const misspelt = opened.find((d) => d.data && d.data.replacement);
  const actions = await s.conn.sendRequest(lsp.CodeActionRequest.type,
    { textDocument: { uri }, range: misspelt.range, context: { diagnostics: [misspelt] } });
  assert.equal(actions[0].edit.changes[uri][0].newText, 'circles');

  // Fix both: the family by an incremental edit, the second spacing by deleting its line.
  await s.conn.sendNotification(lsp.DidChangeTextDocumentNotification.type, {
    textDocument: { uri, version: 2 },
    contentChanges: [
      { range: { start: { line: 2, character: 13 }, end: { line: 2, character: 20 } }, text: 'circles' },
      { range: { start: { line: 5, character: 0 }, end: { line: 6, character: 0 } }, text: '' },
    ],
  });
  const fixed = await s.diagnostics(uri, 2);
  fs.writeFileSync(file, text.replace('circels', 'circles').replace('    spacing = 3\n', ''));
  sameAsCheck(fixed, check(file), file);
  assert.equal(fixed.length, 0);

  // Hover: the property's meaning from the compiler's table, and a value at t = 0.
  const hover = await s.conn.sendRequest(lsp.HoverRequest.type,
    { textDocument: { uri }, position: { line: 3, character: 6 } });
  assert.match(hover.contents.value, /distance between members/);
  assert.match(hover.contents.value, /Value at t = 0: `8`/);

  // Completion in the layer: its properties, not the scene's.
  const items = (await s.conn.sendRequest(lsp.CompletionRequest.type,
    { textDocument: { uri }, position: { line: 5, character: 0 } })).items.map((i) => i.label);
  assert.ok(items.includes('stroke') && items.includes('opacity'), items.join());
  assert.ok(!items.includes('background'));

  // Go to definition: a library family, served read-only.
  const def = await s.conn.sendRequest(lsp.DefinitionRequest.type,
    { textDocument: { uri }, position: { line: 2, character: 15 } });
  assert.equal(def.uri, 'moire-stdlib:///families.moire');
  const lib = await s.conn.sendRequest('workspace/textDocumentContent', { uri: def.uri });
  const line = lib.text.split('\n')[def.range.start.line];
  assert.equal(line.slice(def.range.start.character, def.range.end.character), 'circles');

  // Formatting, where the server offers it: the edits leave a scene without diagnostics.
  if (init.capabilities.documentFormattingProvider) {
    const edits = await s.conn.sendRequest(lsp.DocumentFormattingRequest.type,
      { textDocument: { uri }, options: { tabSize: 4, insertSpaces: true } });
    assert.ok(Array.isArray(edits));
    // The edits all refer to the text before them: applied one by one, last first.
    const last = [...edits].sort((a, b) => b.range.start.line - a.range.start.line ||
                                           b.range.start.character - a.range.start.character);
    await s.conn.sendNotification(lsp.DidChangeTextDocumentNotification.type,
      { textDocument: { uri, version: 3 }, contentChanges: last.map((e) => ({ range: e.range, text: e.newText })) });
    assert.equal((await s.diagnostics(uri, 3)).length, 0);
  }

  await shutDown(s);
});

test('a param: hover, the words after its value, and a rename moire check accepts', async (t) => {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'moire-lsp-'));
  const file = path.join(dir, 'scene.moire');
  const text = 'param gap = 6 in 2 .. 12 step 0.5 unit px\n' +
               'layer a { family = circles; spacing = gap * 2 }\n';
  fs.writeFileSync(file, text);
  const uri = pathToFileURL(file).href;
  const s = start();
  t.after(() => s.proc.kill());
  await initialize(s.conn);
  await s.conn.sendNotification(lsp.DidOpenTextDocumentNotification.type,
    { textDocument: { uri, languageId: 'moire', version: 1, text } });
  sameAsCheck(await s.diagnostics(uri, 1), check(file), file);

  const hover = await s.conn.sendRequest(lsp.HoverRequest.type,
    { textDocument: { uri }, position: { line: 1, character: 39 } });
  assert.match(hover.contents.value, /param gap = 6 in 2 \.\. 12 step 0\.5 unit px/);
  assert.match(hover.contents.value, /from 2 to 12, in steps of 0\.5, shown in px/);

  const words = (await s.conn.sendRequest(lsp.CompletionRequest.type,
    { textDocument: { uri }, position: { line: 0, character: 14 } })).items.map((i) => i.label);
  assert.deepEqual(words, ['in', 'step', 'unit']);

  const edit = await s.conn.sendRequest(lsp.RenameRequest.type,
    { textDocument: { uri }, position: { line: 0, character: 7 }, newName: 'ring_gap' });
  const edits = [...edit.changes[uri]].sort((a, b) => b.range.start.line - a.range.start.line ||
                                                      b.range.start.character - a.range.start.character);
  const lines = text.split('\n');
  for (const e of edits) {
    const l = lines[e.range.start.line];
    lines[e.range.start.line] = l.slice(0, e.range.start.character) + e.newText + l.slice(e.range.end.character);
  }
  fs.writeFileSync(file, lines.join('\n'));
  assert.equal(edits.length, 2);
  assert.deepEqual(check(file), []);
  assert.match(lines.join('\n'), /param ring_gap = 6 in 2/);
  await shutDown(s);
});

// The frames of a raw byte stream from the server.
function frames(buffer) {
  const out = [];
  let rest = buffer;
  for (;;) {
    const end = rest.indexOf('\r\n\r\n');
    if (end < 0) return out;
    const length = Number(/Content-Length: (\d+)/i.exec(rest.subarray(0, end).toString())[1]);
    if (rest.length < end + 4 + length) return out;
    out.push(JSON.parse(rest.subarray(end + 4, end + 4 + length).toString()));
    rest = rest.subarray(end + 4 + length);
  }
}

test('malformed frames get JSON-RPC errors and the server stays up', async (t) => {
  const proc = spawn(moire, ['lsp'], { stdio: ['pipe', 'pipe', 'inherit'] });
  t.after(() => proc.kill());
  let received = Buffer.alloc(0);
  proc.stdout.on('data', (d) => { received = Buffer.concat([received, d]); });
  const frame = (body) => `Content-Length: ${Buffer.byteLength(body)}\r\n\r\n${body}`;
  proc.stdin.write('Content-Length: lots\r\n\r\n');
  proc.stdin.write(frame('{"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {}}'));
  proc.stdin.write(frame('{this is not json'));
  proc.stdin.write(frame('{"jsonrpc": "2.0", "id": 2, "method": "moire/noSuchMethod"}'));
  proc.stdin.write(frame('{"jsonrpc": "2.0", "id": 3, "method": "textDocument/hover", "params": {"x": 1}}'));
  proc.stdin.write(frame('{"jsonrpc": "2.0", "id": 4, "method": "shutdown"}'));
  proc.stdin.write(frame('{"jsonrpc": "2.0", "method": "exit"}'));
  const code = await new Promise((resolve) => proc.on('exit', resolve));
  assert.equal(code, 0);
  const got = frames(received);
  assert.equal(got.length, 6, JSON.stringify(got));
  assert.equal(got[0].error.code, lsp.ErrorCodes.ParseError);      // the bad header
  assert.equal(got[0].id, null);
  assert.ok(got[1].result.capabilities);                           // initialize still answered
  assert.equal(got[2].error.code, lsp.ErrorCodes.ParseError);      // not JSON
  assert.equal(got[3].error.code, lsp.ErrorCodes.MethodNotFound);
  assert.equal(got[4].error.code, lsp.ErrorCodes.InvalidParams);
  assert.equal(got[5].id, 4);                                      // shutdown answered
});

test('a document of random bytes is diagnosed, not crashed on', async (t) => {
  const s = start();
  t.after(() => s.proc.kill());
  await initialize(s.conn);
  let seed = 16;
  const random = () => { seed = (seed * 1103515245 + 12345) % 2147483648; return seed; };
  for (let round = 0; round < 5; ++round) {
    const uri = `file:///random/${round}.moire`;
    const bytes = Buffer.alloc(300 + round * 100, 0).map(() => random() & 0xff);
    const text = bytes.toString('latin1') + bytes.toString('utf8');
    await s.conn.sendNotification(lsp.DidOpenTextDocumentNotification.type,
      { textDocument: { uri, languageId: 'moire', version: 1, text } });
    const diagnostics = await s.diagnostics(uri, 1);
    assert.ok(Array.isArray(diagnostics));
    await s.conn.sendRequest(lsp.HoverRequest.type, { textDocument: { uri }, position: { line: 0, character: 3 } });
    await s.conn.sendRequest(lsp.CompletionRequest.type, { textDocument: { uri }, position: { line: 1, character: 1 } });
    await s.conn.sendRequest(lsp.SemanticTokensRequest.type, { textDocument: { uri } });
  }
  await shutDown(s);
});
