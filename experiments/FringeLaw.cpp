#include "experiments/FringeLaw.h"

#include "compiler/diag/Diagnostics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace moire::exp {

namespace {

double smoothstep(double e0, double e1, double v) {
    // As the IR's smoothstep (ir::Builder::smoothstep), which draws every stroke.
    const double u = std::clamp((v - e0) / (e1 - e0), 0.0, 1.0);
    return u * u * (3.0 - 2.0 * u);
}

bool finite(const LayerSample& s) {
    return std::isfinite(s.index) && std::isfinite(s.distance) && std::isfinite(s.gx) &&
           std::isfinite(s.gy);
}

} // namespace

double coverage(double d, const Stroke& s) {
    const double c = 1.0 - smoothstep(s.h - s.a, s.h + s.a, d);
    return std::isnan(c) ? 0.0 : c; // as the renderer reads NaN coverage
}

FieldProbe::FieldProbe(const std::string& name, const std::string& text) {
    CompileResult r = compileScene(name + ".moire", text,
                                   {.mode = CompileOptions::Mode::Probe, .layerFields = true});
    if (!r.program) {
        std::fprintf(stderr, "%s", r.diagnostics.c_str());
        std::exit(2);
    }
    program_ = std::move(r.program);
    if (program_->layout.numLayers != 2) {
        std::fprintf(stderr, "moire: error: %s: the fringe law needs exactly two layers\n",
                     name.c_str());
        std::exit(2);
    }
    // The frame, once: the probe point stays at the origin and the kernel is evaluated at
    // any pixel of its 1 x 1 image, whose world point is (px - 1/2, 1/2 - py) / zoom.
    std::vector<double> literals = program_->literals;
    std::vector<double> frame(program_->frame.numOutputs);
    InterpEnv env;
    env.params = literals.data();
    env.numParams = literals.size();
    env.outputs = frame.data();
    Interpreter(program_->frame).run(env, regs_);
    const int u = program_->numUniforms;
    uniforms_.assign(frame.begin(), frame.begin() + u);
    zoom_ = frame[u + lower::OutputLayout::kSettingZoom];
    if (frame[u + lower::OutputLayout::kSettingTurn] != 0.0) {
        std::fprintf(stderr, "moire: error: %s: a turned camera is not supported here\n",
                     name.c_str());
        std::exit(2);
    }
    kernel_ = std::make_unique<Interpreter>(program_->kernel);
    outputs_.resize(program_->kernel.numOutputs);
}

FieldProbe::~FieldProbe() = default;

void FieldProbe::run(double x, double y) {
    InterpEnv env;
    env.pixelX = 0.5 + x * zoom_;
    env.pixelY = 0.5 - y * zoom_;
    env.imageW = env.imageH = 1.0;
    env.uniforms = uniforms_.data();
    env.numUniforms = uniforms_.size();
    env.outputs = outputs_.data();
    kernel_->run(env, regs_);
}

void FieldProbe::at(double x, double y, LayerSample out[2]) {
    run(x, y);
    const lower::OutputLayout& l = program_->layout;
    for (int i = 0; i < 2; ++i)
        out[i] = {outputs_[l.indexSlot(i)], outputs_[l.distanceSlot(i)], outputs_[l.gradXSlot(i)],
                  outputs_[l.gradYSlot(i)]};
}

double periodicDistance(double v) {
    return std::abs(v - std::round(v));
}

double strokeProfile(double u, double w, double b) {
    return 1.0 - smoothstep(w - b, w + b, periodicDistance(u));
}

double phi(double delta, double w1, double b1, double w2, double b2, int nodes) {
    double sum = 0;
    for (int j = 0; j < nodes; ++j) {
        const double v = (j + 0.5) / nodes;
        const double a1 = strokeProfile(v, w1, b1), a2 = strokeProfile(v - delta, w2, b2);
        sum += a1 + a2 - a1 * a2;
    }
    return sum / nodes;
}

double phiHardEdged(double delta, double w1, double w2) {
    const double overlap = std::max(0.0, w1 + w2 - periodicDistance(delta));
    return 2 * w1 + 2 * w2 - std::min(2 * std::min(w1, w2), overlap);
}

Window measureWindow(FieldProbe& probe, double x, double y, const Stroke stroke[2],
                     const WindowSettings& settings) {
    Window win;
    LayerSample c[2];
    probe.at(x, y, c);
    if (!finite(c[0]) || !finite(c[1])) {
        win.excluded = "undefined";
        return win;
    }
    const double gx = 0.5 * (c[0].gx + c[1].gx), gy = 0.5 * (c[0].gy + c[1].gy);
    const double g = std::hypot(gx, gy);
    if (!(g > 0)) {
        win.excluded = "undefined";
        return win;
    }
    win.D = c[0].index - c[1].index;
    win.eta = std::hypot(c[0].gx - c[1].gx, c[0].gy - c[1].gy) / g;
    const double T = 1.0 / g, ux = gx / g, uy = gy / g;
    double w[2], b[2], len[2], ang[2];
    for (int i = 0; i < 2; ++i) {
        len[i] = std::hypot(c[i].gx, c[i].gy);
        w[i] = stroke[i].h * len[i];
        b[i] = stroke[i].a * len[i];
        ang[i] = std::atan2(c[i].gy, c[i].gx);
    }
    // The hypotheses of Theorem 2, in the empirical form of §4.5: strokes clear of the far
    // side of the period, and each carrier's gradient steady in direction and length across
    // the window (read at evenly spaced points of S, its ends included).
    if (w[0] + b[0] > 0.45 || w[1] + b[1] > 0.45) win.excluded = "merged";
    double left[2] = {0, 0}, right[2] = {0, 0}; // the most each turns either way
    double lo[2] = {len[0], len[1]}, hi[2] = {len[0], len[1]};
    const int m = settings.gradientSamples;
    for (int k = 0; k < m && !win.excluded; ++k) {
        const double t = T * (double(k) / (m - 1) - 0.5);
        LayerSample s[2];
        probe.at(x + t * ux, y + t * uy, s);
        if (!finite(s[0]) || !finite(s[1])) {
            win.excluded = "undefined";
            break;
        }
        for (int i = 0; i < 2; ++i) {
            const double l = std::hypot(s[i].gx, s[i].gy);
            // The turn from the centre's direction, wrapped to (-pi, pi].
            const double d = std::remainder(std::atan2(s[i].gy, s[i].gx) - ang[i], 2 * M_PI);
            left[i] = std::max(left[i], d);
            right[i] = std::min(right[i], d);
            lo[i] = std::min(lo[i], l);
            hi[i] = std::max(hi[i], l);
        }
    }
    for (int i = 0; i < 2 && !win.excluded; ++i) {
        // Bending: the spread of the gradient's direction over the window (which, where the
        // law applies, is within a quarter of the layer's own period).
        if (left[i] - right[i] > 0.15)
            win.excluded = "bent";
        else if ((hi[i] - lo[i]) / len[i] > 0.15)
            win.excluded = "uneven";
    }
    if (win.excluded) return win;

    // The exact directional mean of the union along S: midpoint samples of the true per-layer
    // coverage, each layer's stroke at its own distance field.
    const int n = settings.coverageSamples;
    double sum = 0;
    for (int j = 0; j < n; ++j) {
        const double t = T * ((j + 0.5) / n - 0.5);
        LayerSample s[2];
        probe.at(x + t * ux, y + t * uy, s);
        const double a1 = coverage(s[0].distance, stroke[0]);
        const double a2 = coverage(s[1].distance, stroke[1]);
        sum += a1 + a2 - a1 * a2;
    }
    win.measured = sum / n;
    win.predicted = phi(win.D, w[0], b[0], w[1], b[1], settings.phiNodes);
    return win;
}

} // namespace moire::exp
