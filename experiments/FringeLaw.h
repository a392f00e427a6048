// The fringe law of spec §4.1 (Theorem 2, Eq. 7) measured on a compiled scene: the layers'
// own index, distance and gradient fields, read on the reference interpreter in double, give
// the exact one-period directional mean of the union's ink at a point, and the law's
// prediction Phi(D) from the same fields at the window centre. The verification of §4.5
// (experiments/fringe_law.cpp) runs this over the frames of twelve scene pairs.
#pragma once

#include "compiler/backend/interp/Interpreter.h"
#include "compiler/Compile.h"

#include <memory>
#include <string>
#include <vector>

namespace moire::exp {

// One layer's fields at a world point.
struct LayerSample {
    double index = 0, distance = 0, gx = 0, gy = 0;
};

// A two-layer scene compiled with its layers' fields as outputs, evaluated at any world
// point. Every layer's gradient is the kernel's own, from AD: a walking layer's too, through
// its solver's result (its index is found by search).
class FieldProbe {
  public:
    // Compiles `text`; on an error in it, prints the diagnostics and exits with status 2.
    FieldProbe(const std::string& name, const std::string& text);
    ~FieldProbe();

    // Both layers' fields at world point (x, y).
    void at(double x, double y, LayerSample out[2]);

  private:
    void run(double x, double y);

    std::unique_ptr<SceneProgram> program_;
    std::unique_ptr<Interpreter> kernel_;
    std::vector<double> uniforms_, outputs_, regs_;
    double zoom_ = 1.0;
};

// The renderer's stroke in world units: half-width h = stroke / 2 (the true width, no
// hairline floor) and antialias half-band a (0.7 px).
struct Stroke {
    double h, a;
};
// Its coverage at distance d (Eq. 4, one opaque layer): 1 - smoothstep(h - a, h + a, d).
double coverage(double d, const Stroke& s);

// The index-space stroke profile A(u) = 1 - smoothstep(w - b, w + b, pd(u, 1)) of §4.1, and
// Phi(Delta) of Eq. 7 by the midpoint rule over `nodes` points of one period (the integrand
// is periodic, so the rule converges fast).
double strokeProfile(double u, double w, double b);
double phi(double delta, double w1, double b1, double w2, double b2, int nodes = 1024);
// Eq. 8: the hard-edged limit b -> 0, valid for w1 + w2 <= 1/2 (an independent check of phi).
double phiHardEdged(double delta, double w1, double w2);
// The distance from v to the nearest integer.
double periodicDistance(double v);

// Everything measured about the window at one point.
struct Window {
    // Why the point is not admissible, or nullptr: "undefined" (a field is not finite or the
    // mean gradient vanishes), "merged" (w_i + b_i > 0.45), "bent" (a carrier's gradient turns
    // more than 0.15 rad across the window), "uneven" (a gradient's length varies more than
    // 15% across it).
    const char* excluded = nullptr;
    double eta = 0;       // the (1, -1) heterodyne ratio at the centre, Eq. 10
    double D = 0;         // idx1 - idx2 at the centre
    double measured = 0;  // the mean ink of the union over S
    double predicted = 0; // Phi(D) at the centre
};

struct WindowSettings {
    int coverageSamples = 128; // midpoint samples of the ink along S
    int gradientSamples = 9;   // points along S (ends included) where the gradients are read
    int phiNodes = 1024;
};

// The window S = p + [-T/2, T/2] u of Theorem 2 at p, with u the direction of the mean index
// gradient and T = 1 / |g|; both layers opaque black, composited as a union.
Window measureWindow(FieldProbe& probe, double x, double y, const Stroke stroke[2],
                     const WindowSettings& settings);

} // namespace moire::exp
