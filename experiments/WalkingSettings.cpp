#include "experiments/WalkingSettings.h"

#include "compiler/backend/interp/Interpreter.h"
#include "compiler/lower/WalkingFamily.h"
#include "compiler/Parameters.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fmt/format.h>
#include <numbers>

namespace moire::exp {

namespace ref = moire::reference;

const std::array<Shape, 5>& sweepShapes() {
    static const std::array<Shape, 5> shapes = {{
        {"circle", "circles", 0, ""},
        {"triangle", "triangles", 3, ""},
        {"square", "squares", 4, ""},
        {"hexagon", "hexagons", 6, ""},
        {"nonagon", "ngon", 9, "sides = 9; "},
    }};
    return shapes;
}

ref::Walking walkingOf(const WalkSetting& s) {
    return {sweepShapes()[s.shape].facets,       s.spacing, s.phase, s.offsetX, s.offsetY,
            s.turnDeg * std::numbers::pi / 180.0};
}

std::vector<WalkSetting> walkGrid(const GridAxes& axes) {
    std::vector<WalkSetting> out;
    for (int shape = 0; shape < static_cast<int>(sweepShapes().size()); ++shape)
        for (double s : axes.spacings)
            for (double f : axes.offsets)
                for (double dir : axes.directionsDeg) {
                    if (f == 0 && dir != axes.directionsDeg.front()) continue;
                    const double a = dir * std::numbers::pi / 180;
                    for (double t : axes.turnsDeg)
                        for (double z : axes.zooms) {
                            WalkSetting w;
                            w.shape = shape;
                            w.spacing = s;
                            w.offsetX = f * s * std::cos(a);
                            w.offsetY = f * s * std::sin(a);
                            w.turnDeg = t;
                            w.zoom = z;
                            out.push_back(w);
                        }
                }
    return out;
}

struct WalkingKernel::Impl {
    CompileResult compiled;
    std::unique_ptr<Interpreter> interp;
    std::vector<double> literals, out, regs;
    FrameValues fv;
    InterpEnv env;
};

namespace {

// Every number the grid varies is a param, so that one compile serves every setting.
std::string sceneText(const Shape& shape) {
    return fmt::format("param sp = 10\nparam ph = 0\nparam off = (0, 0)\nparam tw = 0deg\n"
                       "param zm = 1\n"
                       "scene {{ size = ({}, {}) }}\ncamera {{ zoom = zm }}\n"
                       "layer {{ family = {}; {}spacing = sp; phase = ph; offset = off; "
                       "turn = tw; stroke = {} }}\n",
                       kFrameW, kFrameH, shape.family, shape.extra, kStroke);
}

[[noreturn]] void fail(const std::string& why) {
    std::fprintf(stderr, "%s\n", why.c_str());
    std::exit(1);
}

} // namespace

WalkingKernel::WalkingKernel(int shape, const lower::WalkingVariant& variant,
                             std::optional<sema::FilterMode> filter)
    : impl_(std::make_unique<Impl>()) {
    CompileOptions opt;
    opt.filter = filter;
    opt.layerFields = true;
    opt.tally = true;
    opt.walking = variant;
    impl_->compiled = compileScene("sweep.moire", sceneText(sweepShapes()[shape]), opt);
    if (!impl_->compiled.program) fail(impl_->compiled.diagnostics);
    const SceneProgram& p = *impl_->compiled.program;
    impl_->interp = std::make_unique<Interpreter>(p.kernel);
    impl_->literals = p.literals;
    impl_->out.assign(p.kernel.numOutputs, 0.0);
}

WalkingKernel::~WalkingKernel() = default;

void WalkingKernel::set(const WalkSetting& s) {
    const SceneProgram& p = *impl_->compiled.program;
    auto param = [&](const char* name, std::initializer_list<double> v) {
        for (const Parameter& q : p.parameters)
            if (q.name == name) {
                std::vector<double> value(v);
                setParameterValue(q, value, impl_->literals);
                return;
            }
        fail(std::string("no param ") + name);
    };
    param("sp", {s.spacing});
    param("ph", {s.phase});
    param("off", {s.offsetX, s.offsetY});
    param("tw", {s.turnDeg * std::numbers::pi / 180.0});
    param("zm", {s.zoom});
    FrameRequest req;
    req.literals = &impl_->literals;
    std::string diags;
    if (!evaluateFrame(p, req, impl_->fv, diags)) fail(diags);
    InterpEnv& env = impl_->env;
    env.imageW = impl_->fv.width;
    env.imageH = impl_->fv.height;
    env.uniforms = impl_->fv.uniforms.data();
    env.numUniforms = impl_->fv.uniforms.size();
    env.outputs = impl_->out.data();
    pixel_ = impl_->fv.pixelSize;
    band_ = lower::strokeBandOf(kStroke, pixel_);
    guard_ = lower::walkGuard(band_, s.spacing);
}

Solved WalkingKernel::at(double pixelX, double pixelY) {
    impl_->env.pixelX = pixelX;
    impl_->env.pixelY = pixelY;
    impl_->interp->run(impl_->env, impl_->regs);
    const lower::OutputLayout& layout = impl_->compiled.program->layout;
    Solved s;
    s.distance = impl_->out[layout.distanceSlot(0)];
    s.nLo = impl_->out[layout.aux0Slot(0)];
    s.nHi = impl_->out[layout.aux1Slot(0)];
    s.evaluations = static_cast<double>(Interpreter::lastTally(lower::kRadiusTally));
    s.ink = 1.0 - impl_->out[0];
    return s;
}

std::array<double, 2> WalkingKernel::world(double pixelX, double pixelY) const {
    // The scene's camera: centred on the origin, not turned, y up.
    return {(pixelX - kFrameW * 0.5) * pixel_, (kFrameH * 0.5 - pixelY) * pixel_};
}

std::vector<std::array<double, 2>> haltonPixels(int n, int w, int h) {
    auto radical = [](int i, int base) {
        double f = 1, r = 0;
        for (; i > 0; i /= base) {
            f /= base;
            r += f * (i % base);
        }
        return r;
    };
    std::vector<std::array<double, 2>> out;
    for (int i = 1; i <= n; ++i) out.push_back({radical(i, 2) * w, radical(i, 3) * h});
    return out;
}

double coverageOf(double d, const lower::StrokeBandT<double>& band) {
    const double u = std::clamp((d - (band.h - band.a)) / (2 * band.a), 0.0, 1.0);
    return 1.0 - u * u * (3 - 2 * u);
}

double intervalSpan(const ref::Walking& w, double px, double py, double guard) {
    // Eq. 31, written out again from the spec (not the kernel's code), with §7.6's branches.
    const double r = std::hypot(px, py), len = std::hypot(w.offsetX, w.offsetY);
    const double kappa = w.facets == 0 ? 1.0 : std::cos(std::numbers::pi / w.facets);
    const double m = ref::drift(w), s = w.spacing;
    const double lo = std::max(0.0, std::floor((kappa * r - w.phase - guard) / (s + kappa * len)));
    double hi;
    if (m < s)
        hi = std::ceil((r - w.phase + guard) / (s - m));
    else if (m > s)
        hi = std::ceil((r + w.phase + guard) / (m - s));
    else
        return INFINITY;
    return std::max(0.0, hi - lo) + 1;
}

std::vector<WalkSetting> intervalGrid() {
    std::vector<WalkSetting> out;
    for (const WalkSetting& w :
         walkGrid({.spacings = {1, 2, 3, 5, 8, 12, 20, 40, 80},
         .offsets = {0, 0.1, 0.25, 0.4, 0.55, 0.7, 0.8, 0.9, 0.95, 1.0, 1.05, 1.2, 1.5},
         .directionsDeg = {0, 30, 75},
         .turnsDeg = {0, 0.05, 0.2, 1, 3, 10},
         .zooms = {0.1, 0.15, 0.4, 1, 2.5}}))
        if (w.offsetX != 0 || w.offsetY != 0 || w.turnDeg != 0) out.push_back(w);
    return out;
}

} // namespace moire::exp
