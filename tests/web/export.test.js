// `moire export`: the page it writes, opened in headless Chromium (software WebGL2 through
// SwiftShader), draws the same picture as `moire render` of the same scene, size and time,
// within 2/255 per channel, and a slider changes it as `moire render -D` does.
"use strict";
const { test, before, after } = require("node:test");
const assert = require("node:assert");
const { execFileSync } = require("node:child_process");
const fs = require("node:fs");
const os = require("node:os");
const path = require("node:path");
const puppeteer = require("puppeteer-core");
const { decodePng } = require("./png-decode.js");

const moire = process.env.MOIRE_BINARY;
const source = process.env.MOIRE_SOURCE_DIR;
let browser, dir;

before(async () => {
  dir = fs.mkdtempSync(path.join(os.tmpdir(), "moire-export-"));
  browser = await puppeteer.launch({
    executablePath: process.env.MOIRE_CHROMIUM,
    headless: true,
    // WebGL2 without a GPU: ANGLE over SwiftShader, which Chromium keeps behind this flag.
    args: ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
           "--ignore-gpu-blocklist", "--disable-dev-shm-usage"],
  });
});

after(async () => {
  if (browser) await browser.close();
  if (dir) fs.rmSync(dir, { recursive: true, force: true });
});

function run(args) {
  return execFileSync(moire, args, { cwd: source, stdio: ["ignore", "pipe", "pipe"] });
}

// The page's picture after `prepare` (run in the page) and a draw, as RGBA rows from the top.
async function pagePixels(file, prepare = () => {}) {
  const page = await browser.newPage();
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  await page.goto("file://" + file);
  await page.waitForFunction(() => window.moirePiece && (window.moirePiece.ready || window.moirePiece.problem));
  const problem = await page.evaluate(() => window.moirePiece.problem);
  assert.strictEqual(problem, "", "the page says: " + problem);
  await page.evaluate(prepare);
  const pixels = await page.evaluate(() => {
    window.moirePiece.draw();
    return Array.from(window.moirePiece.pixels());
  });
  await page.close();
  assert.deepStrictEqual(errors, []);
  return Uint8Array.from(pixels);
}

// How the page's picture differs from the PNG: the largest difference, and the share of
// samples within 2/255.
function compare(got, png) {
  assert.strictEqual(got.length, png.rgba.length);
  let worst = 0, over = 0;
  for (let i = 0; i < got.length; ++i) {
    const d = Math.abs(got[i] - png.rgba[i]);
    worst = Math.max(worst, d);
    if (d > 2) ++over;
  }
  return { worst, within: 1 - over / got.length };
}

// One scene: exported and rendered at the same size and time; every sample within 2/255.
// The name "default" is the embedded default scene (no scene argument).
async function matches(name, { size = "240x160", time = 0, render = [], prepare } = {}) {
  const scene = name === "default" ? [] : [path.join("examples", name + ".moire")];
  const html = path.join(dir, `${name}-${time}.html`), png = path.join(dir, `${name}-${time}.png`);
  run(["export", ...scene, "-o", html, "--size", size, "--time", String(time), "--paused", "-q"]);
  run(["render", ...scene, "-o", png, "--size", size, "--time", String(time), "-q", ...render]);
  const want = decodePng(fs.readFileSync(png));
  const got = await pagePixels(html, prepare);
  const d = compare(got, want);
  assert.ok(d.worst <= 2, `${name} at t=${time}: ${(100 * (1 - d.within)).toFixed(3)}% of ` +
            `samples differ by more than 2/255 (worst ${d.worst})`);
  return d;
}

test("two rings, and the default scene: the exported page draws what moire render draws", async () => {
  await matches("two_rings");
  await matches("default");
});

// Circles 0.7 apart and 0.1 wide at a world unit a pixel: 14% ink under the mean filter,
// solid ink point-sampled (docs/filtering.md).
function inkOf(rgba) {
  let sum = 0;
  for (let i = 0; i < rgba.length; i += 4) sum += 1 - rgba[i] / 255;
  return sum / (rgba.length / 4);
}

test("--filter: the page draws what render --filter draws", async () => {
  const scene = path.join(dir, "fine.moire");
  fs.writeFileSync(scene, "scene { size = (160, 120) }\n" +
                   "layer a { family = circles; spacing = 0.7; stroke = 0.1 }\n");
  const ink = {};
  for (const filter of ["point", "mean"]) {
    const html = path.join(dir, `fine-${filter}.html`), png = path.join(dir, `fine-${filter}.png`);
    run(["export", scene, "-o", html, "--paused", "-q", "--filter", filter]);
    run(["render", scene, "-o", png, "-q", "--filter", filter]);
    const got = await pagePixels(html);
    const d = compare(got, decodePng(fs.readFileSync(png)));
    assert.ok(d.within >= 0.999, `${filter}: ${(100 * (1 - d.within)).toFixed(3)}% of samples ` +
              `differ by more than 2/255 (worst ${d.worst})`);
    ink[filter] = inkOf(got);
  }
  assert.ok(ink.mean < 0.3, `mean ink ${ink.mean}`);
  assert.ok(ink.point > 0.9, `point ink ${ink.point}`);
});

test("a walking family: the walk's loops run in the fragment shader", async () => {
  await matches("walking_squares");
  await matches("unwinding_walk");
});

test("animated scenes at a given time, a walking family among them", async () => {
  await matches("morphing_shapes", { time: 3.7 });
  await matches("unwinding_walk", { time: 5.5 });
  await matches("unwinding_walk", { time: 13.25 });
});

test("the clock's controls: the time slider scrubs, play runs the clock, pause stops it", async () => {
  // Exported at t = 0, then scrubbed to 2.25 s by the slider, as a person would.
  const scene = "examples/morphing_shapes.moire";
  const html = path.join(dir, "clock.html"), png = path.join(dir, "clock.png");
  run(["export", scene, "-o", html, "--size", "200x120", "--paused", "-q"]);
  run(["render", scene, "-o", png, "--size", "200x120", "--time", "2.25", "-q"]);
  const got = await pagePixels(html, () => {
    const slider = document.getElementById("time");
    slider.value = "2.25";
    slider.dispatchEvent(new Event("input"));
  });
  assert.ok(compare(got, decodePng(fs.readFileSync(png))).worst <= 2);

  const page = await browser.newPage();
  await page.goto("file://" + html);
  await page.waitForFunction(() => window.moirePiece.ready);
  assert.strictEqual(await page.evaluate(() => window.moirePiece.playing), false);
  await page.click("#play");
  await page.waitForFunction(() => window.moirePiece.time > 0.2);
  await page.click("#play");
  const stopped = await page.evaluate(() => window.moirePiece.time);
  await new Promise((done) => setTimeout(done, 200));
  assert.strictEqual(await page.evaluate(() => window.moirePiece.time), stopped);
  assert.strictEqual(await page.evaluate(() => document.getElementById("play").textContent), "Play");
  await page.close();
});

test("every example scene", async () => {
  const names = fs.readdirSync(path.join(source, "examples"))
    .filter((f) => f.endsWith(".moire")).map((f) => f.slice(0, -6)).sort();
  assert.ok(names.length > 10);
  for (const name of names) await matches(name, { size: "160x120" });
});

// A scene of every kind of param (docs/language.md's own example).
const paramScene = `scene { size = (320, 200) }
param gap   = 8 in 4 .. 20 step 0.5 unit px
param tilt  = 10deg in 0deg .. 45deg
param shift = (10, 0) in -40 .. 40
param ink   = #18181c
param bold  = false
param wide  = gap * 1.5 + sin(t) in 0 .. 25
param thin  = 1.5 in -1 .. 4
layer a { family = circles; spacing = gap; color = ink; stroke = thin }
layer b { family = lines; spacing = wide; rotation = tilt; origin = shift
          stroke = select(bold, 3, 1.5) }
`;

// The page exported from `paramScene` (with `exportArgs`), changed by `prepare`, against
// `moire render -D ...`.
async function paramsMatch(label, renderDefines, prepare, exportArgs = []) {
  const scene = path.join(dir, "params.moire");
  fs.writeFileSync(scene, paramScene);
  const html = path.join(dir, `params-${label}.html`), png = path.join(dir, `params-${label}.png`);
  run(["export", scene, "-o", html, "--paused", "-q", ...exportArgs]);
  run(["render", scene, "-o", png, "-q", ...renderDefines.flatMap((d) => ["-D", d])]);
  const got = await pagePixels(html, prepare);
  const d = compare(got, decodePng(fs.readFileSync(png)));
  assert.ok(d.worst <= 2, `${label}: worst ${d.worst}, ${(100 * (1 - d.within)).toFixed(3)}% over 2`);
}

// Moves an input of the page as a person would: its value, then the event it fires.
function setInput(id, value, event = "input") {
  return [id, value, event];
}

test("params: as exported, the page draws what render draws", async () => {
  await paramsMatch("plain", [], () => {});
});

test("params: each kind of slider redraws as moire render -D draws that value", async () => {
  const drive = (moves) => new Function(`for (const [id, value] of ${JSON.stringify(moves)}) {
      const input = document.getElementById(id);
      if (input.type === "checkbox") input.checked = value; else input.value = value;
      input.dispatchEvent(new Event("input"));
    }`);
  await paramsMatch("gap", ["gap=12.5"], drive([setInput("param-gap", "12.5")]));
  // Degrees on the slider, as the scene wrote the angle.
  await paramsMatch("tilt", ["tilt=30deg"], drive([setInput("param-tilt", "30")]));
  await paramsMatch("shift", ["shift=(-15, 5)"],
                    drive([setInput("param-shift", "-15"), setInput("param-shift-1", "5")]));
  await paramsMatch("ink", ["ink=#c03020"], drive([setInput("param-ink", "#c03020")]));
  await paramsMatch("bold", ["bold=true"], drive([setInput("param-bold", true)]));
  // A param whose default is an expression, set outright.
  await paramsMatch("wide", ["wide=25"], drive([setInput("param-wide", "25")]));
});

test("params: setParameter, and -D on export sets where the sliders start", async () => {
  await paramsMatch("api", ["gap=6", "shift=(3, -7)"], () => {
    window.moirePiece.setParameter("gap", [6]);
    window.moirePiece.setParameter("shift", [3, -7]);
  });
  await paramsMatch("defined", ["gap=16"], () => {}, ["-D", "gap=16"]);
});

test("params: a value the picture cannot take is said, as render says it", async () => {
  const scene = path.join(dir, "params.moire");
  fs.writeFileSync(scene, paramScene);
  const html = path.join(dir, "params-bad.html");
  run(["export", scene, "-o", html, "--paused", "-q"]);
  const page = await browser.newPage();
  await page.goto("file://" + html);
  await page.waitForFunction(() => window.moirePiece.ready);
  const said = async (name, values) => page.evaluate((n, v) => {
    window.moirePiece.setParameter(n, v);
    return window.moirePiece.problem;
  }, name, values);
  // A stroke of -0.5 is in the param's range but no stroke can be negative.
  assert.match(await said("thin", [-0.5]), /'stroke' must be more than 0.*, not -0\.5/);
  assert.strictEqual(await said("thin", [2]), "");
  // A param set past its own range (from script: a slider stops at its ends).
  assert.match(await said("gap", [30]), /param 'gap' must be from 4 to 20, not 30/);
  // wide = 1.5 gap: past its range of 0 .. 25 when gap is 20, inside its own.
  assert.match(await said("gap", [20]), /param 'wide' must be from 0 to 25, not 30/);
  assert.strictEqual(await said("gap", [10]), "");
  await page.close();
});

test("a canvas larger than the browser draws is said so, not drawn in part", async () => {
  const html = path.join(dir, "wide.html");
  run(["export", "examples/two_rings.moire", "-o", html, "--size", "32768x64", "-q"]);
  const page = await browser.newPage();
  await page.goto("file://" + html);
  await page.waitForFunction(() => window.moirePiece.problem !== "");
  assert.match(await page.evaluate(() => window.moirePiece.problem),
               /^This piece is 32768x64 pixels; this browser draws at most \d+x\d+\.$/);
  await page.close();
});

test("the page without WebGL2 says so instead of failing", async () => {
  const html = path.join(dir, "nogl.html");
  run(["export", "examples/two_rings.moire", "-o", html, "-q"]);
  const page = await browser.newPage();
  await page.evaluateOnNewDocument(() => {
    const original = HTMLCanvasElement.prototype.getContext;
    HTMLCanvasElement.prototype.getContext = function (kind, ...rest) {
      return kind === "webgl2" ? null : original.call(this, kind, ...rest);
    };
  });
  await page.goto("file://" + html);
  const problem = await page.evaluate(() => window.moirePiece.problem);
  await page.close();
  assert.match(problem, /needs WebGL2/);
});
