// Helpers of the `moire serve` browser tests: a real server on a free port, requests with and
// without its token, `moire render` to compare with, and Chromium.
'use strict';
const { spawn, execFileSync } = require('node:child_process');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const readline = require('node:readline');
const { decodePng } = require('./png-decode.js');

const moireBinary = process.env.MOIRE_BINARY;

function tempDir() {
  return fs.mkdtempSync(path.join(os.tmpdir(), 'moire-serve-test-'));
}

// Starts `moire serve SCENE --port 0 ARGS...` (with `env` added to the environment) and
// resolves once it printed its address.
function startServe(scene, args = [], env = {}) {
  const proc = spawn(moireBinary, ['serve', scene, '--port', '0', ...args], {
    stdio: ['ignore', 'pipe', 'pipe'],
    env: { ...process.env, ...env },
  });
  let stderr = '';
  proc.stderr.on('data', (d) => (stderr += d));
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`no address in 30 s; stderr:\n${stderr}`)), 30000);
    proc.on('exit', (code) => reject(new Error(`moire serve exited (${code}):\n${stderr}`)));
    readline.createInterface({ input: proc.stdout }).once('line', (url) => {
      clearTimeout(timer);
      const u = new URL(url);
      resolve({
        proc,
        url,
        base: `${u.protocol}//${u.host}`,
        token: u.searchParams.get('token'),
        stderr: () => stderr,
        stop: () =>
          new Promise((done) => {
            if (proc.exitCode !== null) return done(proc.exitCode);
            proc.removeAllListeners('exit');
            proc.on('exit', (code) => done(code));
            proc.kill('SIGTERM');
          }),
      });
    });
  });
}

// fetch() against the server, with its token unless `token` says otherwise.
async function request(server, pathname, { method = 'GET', body, token = server.token } = {}) {
  const url = new URL(pathname, server.base);
  if (token !== null) url.searchParams.set('token', token);
  const init = { method };
  if (body !== undefined) {
    init.body = typeof body === 'string' ? body : JSON.stringify(body);
    init.headers = { 'Content-Type': 'application/json' };
  }
  return fetch(url, init);
}

async function json(server, pathname, options) {
  const response = await request(server, pathname, options);
  return { status: response.status, body: await response.json() };
}

// Polls `probe` (async, truthy when done) until it holds or `ms` pass.
async function waitFor(probe, ms = 30000, what = 'the condition') {
  const end = Date.now() + ms;
  for (;;) {
    const value = await probe();
    if (value) return value;
    if (Date.now() > end) throw new Error(`timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 50));
  }
}

// `moire render SCENE --size WxH ARGS...` decoded.
function render(scene, width, height, args = []) {
  const out = path.join(tempDir(), 'reference.png');
  execFileSync(moireBinary, ['render', scene, '--size', `${width}x${height}`, '-o', out, '-q', ...args]);
  return decodePng(fs.readFileSync(out));
}

async function launchBrowser() {
  const puppeteer = require('puppeteer-core');
  return puppeteer.launch({
    executablePath: process.env.MOIRE_CHROMIUM,
    headless: true,
    // sRGB output: the canvas keeps the PNG's bytes as they are.
    args: ['--no-sandbox', '--force-color-profile=srgb', '--disable-gpu', '--disable-dev-shm-usage'],
  });
}

// The largest difference of any channel of any pixel, and how many pixels differ at all.
function compareRgba(a, b) {
  if (a.length !== b.length) throw new Error(`sizes differ: ${a.length} and ${b.length} bytes`);
  let max = 0, differing = 0;
  for (let i = 0; i < a.length; i += 4) {
    let d = 0;
    for (let c = 0; c < 4; ++c) d = Math.max(d, Math.abs(a[i + c] - b[i + c]));
    if (d > 0) ++differing;
    max = Math.max(max, d);
  }
  return { max, differing };
}

module.exports = { compareRgba, decodePng, tempDir, startServe, request, json, waitFor, render, launchBrowser };
