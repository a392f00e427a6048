// Starting the language server as the extension does: `moire lsp` on stdio. Until moire
// has the server, the test says so and skips; with it, the server answers initialize and
// shuts down cleanly.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { test } from 'node:test';
import { hasSubcommand, serverCommand } from '../out/server.js';
import { moire } from './support.mjs';

test('the server command line is moire lsp', () => {
  assert.deepEqual(serverCommand('/opt/bin/moire'), { command: '/opt/bin/moire', args: ['lsp'] });
});

test('subcommands are read from moire --help', () => {
  assert.equal(hasSubcommand(moire, 'render'), true);
  assert.equal(hasSubcommand(moire, 'names'), true);
  assert.equal(hasSubcommand(moire, 'no-such-command'), false);
  assert.equal(hasSubcommand('/nonexistent/moire', 'render'), false);
});

// One LSP message, framed as the protocol frames it.
const frame = (message) => {
  const body = Buffer.from(JSON.stringify(message), 'utf8');
  return Buffer.concat([Buffer.from(`Content-Length: ${body.length}\r\n\r\n`), body]);
};

// The messages in `data` so far, unframed.
function messages(data) {
  const out = [];
  let rest = data;
  for (;;) {
    const end = rest.indexOf('\r\n\r\n');
    if (end < 0) break;
    const length = Number(/Content-Length: *(\d+)/i.exec(rest.subarray(0, end).toString())?.[1]);
    if (rest.length < end + 4 + length) break;
    out.push(JSON.parse(rest.subarray(end + 4, end + 4 + length).toString('utf8')));
    rest = rest.subarray(end + 4 + length);
  }
  return out;
}

test('the server starts from moire on stdio, answers initialize and exits on exit', async (t) => {
  if (!hasSubcommand(moire, 'lsp')) {
    t.skip(`skipped: ${moire} has no lsp subcommand yet (the language server is not built in)`);
    console.log(`skipped: ${moire} has no lsp subcommand yet`);
    return;
  }
  const { command, args } = serverCommand(moire);
  const child = spawn(command, args, { stdio: ['pipe', 'pipe', 'inherit'] });
  let data = Buffer.alloc(0);
  const waitFor = (id) =>
    new Promise((resolve, reject) => {
      const timer = setTimeout(() => reject(new Error(`no answer to request ${id}`)), 20000);
      const look = () => {
        const m = messages(data).find((x) => x.id === id);
        if (m) {
          clearTimeout(timer);
          child.stdout.off('data', onData);
          resolve(m);
        }
      };
      const onData = (d) => {
        data = Buffer.concat([data, d]);
        look();
      };
      child.stdout.on('data', onData);
      look();
    });
  const exited = new Promise((resolve) => child.on('exit', (code) => resolve(code)));
  child.stdin.write(frame({ jsonrpc: '2.0', id: 1, method: 'initialize', params: { processId: process.pid, rootUri: null, capabilities: {} } }));
  const init = await waitFor(1);
  assert.ok(init.result?.capabilities, JSON.stringify(init));
  child.stdin.write(frame({ jsonrpc: '2.0', method: 'initialized', params: {} }));
  child.stdin.write(frame({ jsonrpc: '2.0', id: 2, method: 'shutdown' }));
  const shutdown = await waitFor(2);
  assert.equal(shutdown.result, null);
  child.stdin.write(frame({ jsonrpc: '2.0', method: 'exit' }));
  assert.equal(await exited, 0);
});
