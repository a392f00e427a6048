// The page of a moire piece (`moire export`). Each frame, the scene's frame program (compiled
// to JavaScript) turns the literal table and the clock into the kernel's uniforms; the kernel
// (compiled to a GLSL ES 3.00 fragment shader) draws every pixel of the canvas from them. A
// slider writes a parameter's value into the literal table, so moving it never recompiles.
"use strict";
(() => {
  const data = JSON.parse(document.getElementById("moire-data").textContent);
  const frameProgram = window.moireFrameProgram;
  const canvas = document.getElementById("picture");
  const problem = document.getElementById("problem");
  const controls = document.getElementById("controls");

  const api = { ready: false, problem: "" };
  window.moirePiece = api;

  function say(text) {
    api.problem = text;
    problem.textContent = text;
    problem.hidden = text === "";
  }

  // --- WebGL2: one triangle over the whole canvas, the kernel as its fragment shader ---
  // premultipliedAlpha: false, since the kernel's colour is straight RGBA; the drawing
  // buffer is kept so that the picture can be read back (and saved) between frames.
  const gl = canvas.getContext("webgl2", {
    alpha: true, antialias: false, depth: false, premultipliedAlpha: false,
    preserveDrawingBuffer: true,
  });
  if (!gl) {
    say("This piece needs WebGL2, which this browser does not offer (or has turned off).");
    return;
  }
  const most = gl.getParameter(gl.MAX_FRAGMENT_UNIFORM_VECTORS);
  if (data.uniformVectors > most) {
    say(`This piece needs ${data.uniformVectors} uniform vectors; this browser offers ${most}.`);
    return;
  }
  const [widest, tallest] = gl.getParameter(gl.MAX_VIEWPORT_DIMS);
  if (canvas.width > widest || canvas.height > tallest) {
    say(`This piece is ${canvas.width}x${canvas.height} pixels; this browser draws at most ` +
        `${widest}x${tallest}.`);
    return;
  }
  const vertexSource = `#version 300 es
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}`;
  function shader(type, source) {
    const s = gl.createShader(type);
    gl.shaderSource(s, source);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS))
      throw new Error("the browser could not compile the shader: " + gl.getShaderInfoLog(s));
    return s;
  }
  let program;
  try {
    program = gl.createProgram();
    gl.attachShader(program, shader(gl.VERTEX_SHADER, vertexSource));
    gl.attachShader(program, shader(gl.FRAGMENT_SHADER, data.shader));
    gl.linkProgram(program);
    if (!gl.getProgramParameter(program, gl.LINK_STATUS))
      throw new Error("the browser could not link the shader: " + gl.getProgramInfoLog(program));
  } catch (e) {
    say(String(e.message));
    return;
  }
  const uniformsAt = gl.getUniformLocation(program, "m_u");
  const imageAt = gl.getUniformLocation(program, "m_image");
  gl.bindVertexArray(gl.createVertexArray());

  // --- The frame: literals and clock -> uniforms, then the picture ---
  const literals = Float64Array.from(data.literals, (v) => (v === null ? NaN : v));
  const outputs = new Float64Array(data.frameOutputs);
  const uniforms = new Float32Array(4 * data.uniformVectors);

  // What the frame's values must be for the picture to be drawn (as `moire render` checks
  // them); the first that is not, in words, or "".
  const rules = {
    range: (v, c) => (v >= c.lo && v <= c.hi) || `from ${+c.lo.toPrecision(6)} to ${+c.hi.toPrecision(6)}`,
    finite: (v) => Math.abs(v) <= 1e12 || "between -1e12 and 1e12",
    positive: (v) => (v > 0 && v <= 1e12) || "more than 0 and at most 1e12",
    spacing: (v) => (v >= 1e-6 && v <= 1e12) || "from 1e-6 to 1e12",
    unit: (v) => (v >= 0 && v <= 1) || "from 0 to 1",
    sides: (v) => (v >= 3 && v <= 1e12 && v === Math.floor(v)) || "a whole number, 3 or more",
    period: (v) => (Number.isFinite(v) && v > 0) || "more than 0",
    delay: (v) => (Number.isFinite(v) && v >= 0) || "0 or more",
    zoom: (v) => (v >= 1e-6 && v <= 1e6) || "from 1e-6 to 1e6",
  };
  function frameProblem() {
    for (const c of data.checks) {
      const v = outputs[c.output];
      const ok = rules[c.rule](v, c);
      if (ok !== true) return `${c.what} must be ${ok}, not ${+v.toPrecision(6)}`;
    }
    return "";
  }

  let time = data.time;
  function draw() {
    frameProgram(literals, time, outputs);
    follow();
    const wrong = frameProblem();
    say(wrong === "" ? "" : "The picture cannot be drawn: " + wrong + ".");
    if (wrong !== "") return false;
    for (let i = 0; i < data.numUniforms; ++i) uniforms[i] = outputs[i];
    gl.viewport(0, 0, canvas.width, canvas.height);
    gl.useProgram(program);
    gl.uniform4fv(uniformsAt, uniforms);
    gl.uniform2f(imageAt, canvas.width, canvas.height);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    return true;
  }

  // --- The clock: play, pause, scrub ---
  // A looping scene's clock wraps at its loop (the least common multiple of its timings'
  // cycles, as `moire clip` finds it); one that only reads t runs on.
  const span = data.loop > 0 ? data.loop : 60;
  let playing = data.playing && data.moves;
  let startClock = 0, startTime = time; // performance.now() and time when play began
  const row = (labelText, input, output) => {
    const label = document.createElement("label");
    label.textContent = labelText;
    if (input.id) label.htmlFor = input.id;
    controls.append(label, input);
    if (output) controls.append(output);
    else input.classList.add("wide");
  };
  const slider = (id, min, max, step, value) => {
    const s = document.createElement("input");
    Object.assign(s, { type: "range", id, min, max, step, value });
    return s;
  };
  const readout = () => document.createElement("output");

  const playButton = document.createElement("button");
  playButton.id = "play";
  const timeSlider = slider("time", 0, span, "any", time);
  const timeText = readout();
  const showTime = () => {
    timeSlider.value = String(time);
    timeText.textContent = time.toFixed(2) + " s";
    playButton.textContent = playing ? "Pause" : "Play";
  };
  if (data.moves) {
    row("", playButton);
    row("t", timeSlider, timeText);
    playButton.addEventListener("click", () => (playing ? api.pause() : api.play()));
    timeSlider.addEventListener("input", () => {
      api.setTime(Number(timeSlider.value));
    });
  }

  function tick(now) {
    if (!playing) return;
    if (startClock === 0) startClock = now;
    let t = startTime + (now - startClock) / 1000;
    if (data.loop > 0) t %= data.loop;
    time = t;
    draw();
    showTime();
    requestAnimationFrame(tick);
  }

  // --- Parameters: a slider (or picker, or box) each, writing the literal table ---
  // A slider writes its param's value slots and sets its switch slot (compiler/Parameters.h);
  // until one is moved, it follows the param's value as the frame program gives it (a
  // default may be an expression of t or of other params). A double click on the name goes
  // back to the default.
  const parameterInputs = new Map(); // name -> { p, values, apply, show }
  frameProgram(literals, time, outputs);
  for (const p of data.parameters) addParameter(p);

  function addParameter(p) {
    const id = "param-" + p.name;
    const values = Array.from(outputs.subarray(p.output, p.output + p.components));
    const apply = () => {
      for (let i = 0; i < p.components; ++i) literals[p.valueSlot + i] = values[i];
      literals[p.setSlot] = 1;
      if (!playing) draw();
    };
    const entry = { p, values, apply, show: () => {} };
    parameterInputs.set(p.name, entry);
    const name = document.createElement("label");
    name.textContent = p.name;
    name.htmlFor = id;
    name.title = "double click: back to the scene's value";
    name.addEventListener("dblclick", () => {
      literals[p.setSlot] = 0;
      if (!playing) draw();
      follow();
    });
    if (p.type === "bool") {
      const box = document.createElement("input");
      Object.assign(box, { type: "checkbox", id });
      box.addEventListener("input", () => {
        values[0] = box.checked ? 1 : 0;
        apply();
      });
      entry.show = () => (box.checked = values[0] !== 0);
      box.classList.add("wide");
      controls.append(name, box);
    } else if (p.type === "color") {
      const pick = document.createElement("input");
      Object.assign(pick, { type: "color", id });
      const hex = (v) => Math.round(Math.min(Math.max(v, 0), 1) * 255).toString(16).padStart(2, "0");
      pick.addEventListener("input", () => {
        for (let i = 0; i < 3; ++i) values[i] = parseInt(pick.value.substr(1 + 2 * i, 2), 16) / 255;
        apply();
      });
      entry.show = () => (pick.value = "#" + values.slice(0, 3).map(hex).join(""));
      pick.classList.add("wide");
      controls.append(name, pick);
    } else {
      // Numbers, angles (in degrees when the scene wrote degrees) and each component of a
      // vector, each its own slider. Without a declared range a slider spans a guess around
      // the value: half a turn each way for an angle, else from 0 to twice the value.
      const degrees = p.unit === "deg";
      const scale = degrees ? 180 / Math.PI : 1;
      const suffix = degrees ? "°" : p.label ? " " + p.label : "";
      const sliders = [], readouts = [];
      for (let i = 0; i < p.components; ++i) {
        const v = values[i], angle = p.type === "angle";
        const lo = p.min ?? (angle ? -Math.PI : v === 0 ? -1 : Math.min(0, 2 * v));
        const hi = p.max ?? (angle ? Math.PI : v === 0 ? 1 : Math.max(0, 2 * v));
        const s = slider(i === 0 ? id : `${id}-${i}`, lo * scale, hi * scale,
                         p.step ? p.step * scale : "any", v * scale);
        const out = readout();
        s.addEventListener("input", () => {
          values[i] = Number(s.value) / scale;
          out.textContent = +(values[i] * scale).toPrecision(6) + suffix;
          apply();
        });
        if (i === 0) controls.append(name);
        else controls.append(Object.assign(document.createElement("label"), { textContent: "" }));
        controls.append(s, out);
        sliders.push(s);
        readouts.push(out);
      }
      entry.show = () => values.forEach((v, i) => {
        sliders[i].value = String(v * scale);
        readouts[i].textContent = +(v * scale).toPrecision(6) + suffix;
      });
    }
    entry.show();
  }

  // After each frame: the sliders not moved show the value the scene gave their param.
  function follow() {
    for (const { p, values, show } of parameterInputs.values()) {
      if (literals[p.setSlot] !== 0) continue;
      for (let i = 0; i < p.components; ++i) values[i] = outputs[p.output + i];
      show();
    }
  }

  // --- What tests and a host page may call ---
  Object.assign(api, {
    draw,
    play() {
      if (!data.moves) return;
      playing = true;
      startClock = 0;
      startTime = time;
      showTime();
      requestAnimationFrame(tick);
    },
    pause() {
      playing = false;
      showTime();
    },
    setTime(t) {
      time = t;
      startClock = 0;
      startTime = t;
      showTime();
      if (!playing) draw();
    },
    // Sets a parameter as its slider does; `values` has one number per component.
    setParameter(name, values) {
      const entry = parameterInputs.get(name);
      if (!entry) throw new Error(`no parameter '${name}'`);
      values.forEach((v, i) => (entry.values[i] = v));
      entry.show();
      entry.apply();
    },
    // The picture's RGBA bytes, rows from the top.
    pixels() {
      const w = canvas.width, h = canvas.height, bytes = new Uint8Array(w * h * 4);
      gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, bytes);
      const rows = new Uint8Array(w * h * 4);
      for (let y = 0; y < h; ++y) rows.set(bytes.subarray((h - 1 - y) * w * 4, (h - y) * w * 4), y * w * 4);
      return rows;
    },
  });
  // Getters, which Object.assign would read once instead of copying.
  Object.defineProperties(api, {
    time: { get: () => time },
    playing: { get: () => playing },
  });

  showTime();
  draw();
  api.ready = true;
  if (playing) api.play();
})();
