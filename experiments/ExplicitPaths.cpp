#include "experiments/ExplicitPaths.h"

#include <algorithm>
#include <cairo.h>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

namespace moire::exp {

namespace {

constexpr double kPi = std::numbers::pi;

std::string number(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.12g", v);
    return buf;
}

int firstMember(const Geometry& g) {
    return g.kind == PairKind::Hyperbolas ? 1 : 0;
}

// How far layer l of a line or hexagon pair is turned.
double turn(const Geometry& g, int l) {
    return kBaseTurn + (l == 1 ? g.rotation : 0);
}

// One layer's block: its family and what sets it apart.
std::string layerText(const Geometry& g, int l) {
    std::string t = "layer l" + std::to_string(l + 1) +
                    " {\n    color = #000000\n    stroke = " + number(g.stroke) +
                    "\n    spacing = " + number(g.spacing[l]) + "\n";
    switch (g.kind) {
    case PairKind::LinesRotated:
    case PairKind::LinesPitch:
        t += "    family = lines\n    angle = " + number(turn(g, l) * 180 / kPi) + "deg\n";
        break;
    case PairKind::Circles:
        t +=
            "    family = circles\n    origin = (" + number(l == 0 ? -g.shift : g.shift) + ", 0)\n";
        break;
    case PairKind::Hexagons:
        t += "    family = hexagons\n    rotation = " + number(turn(g, l) * 180 / kPi) + "deg\n";
        break;
    case PairKind::Hyperbolas:
        t += "    family = hyperbola\n";
        break;
    }
    return t + "}\n";
}

// The polyline of one hyperbola branch x = c cosh u, y = c sinh u (E; the others by
// symmetry), from u = -umax to umax, no chord longer than 0.3 px nor 0.05 in u.
void hyperbolaBranch(cairo_t* cr, double c, int branch, double reach, double pixel) {
    const double umax = std::asinh(reach / c);
    bool first = true;
    for (double u = -umax;;) {
        const double a = c * std::cosh(u), b = c * std::sinh(u);
        double x = a, y = b;
        if (branch == 1) x = -a;
        if (branch == 2) x = b, y = a;
        if (branch == 3) x = b, y = -a;
        if (first)
            cairo_move_to(cr, x, y);
        else
            cairo_line_to(cr, x, y);
        first = false;
        if (u >= umax) break;
        const double speed = c * std::hypot(std::sinh(u), std::cosh(u));
        u = std::min(umax, u + std::min(0.05, 0.3 * pixel / speed));
    }
}

void polygon(cairo_t* cr, double apothem, double turn) {
    const double r = apothem / std::cos(kPi / 6);
    for (int k = 0; k < 6; ++k) {
        const double a = turn + kPi / 6 + k * kPi / 3; // the hexagon's corners
        if (k == 0)
            cairo_move_to(cr, r * std::cos(a), r * std::sin(a));
        else
            cairo_line_to(cr, r * std::cos(a), r * std::sin(a));
    }
    cairo_close_path(cr);
}

} // namespace

const std::vector<PairSpec>& pairSpecs() {
    static const std::vector<PairSpec> all = {
        {"parallel-rotate", PairKind::LinesRotated},   {"parallel-pitch", PairKind::LinesPitch},
        {"circle-circle", PairKind::Circles},          {"hexagon-hexagon", PairKind::Hexagons},
        {"hyperbola-hyperbola", PairKind::Hyperbolas},
    };
    return all;
}

std::string sceneText(const Geometry& g, double zoom, int width) {
    return "scene { size = (" + std::to_string(width) + ", " + std::to_string(width) +
           ") }\ncamera { zoom = " + number(zoom) + " }\n" + layerText(g, 0) + layerText(g, 1);
}

std::string secondLabel(const Geometry& g) {
    char buf[40];
    switch (g.kind) {
    case PairKind::LinesRotated:
    case PairKind::Hexagons:
        std::snprintf(buf, sizeof buf, "%.2fdeg", g.rotation * 180 / kPi);
        break;
    case PairKind::LinesPitch:
    case PairKind::Hyperbolas:
        std::snprintf(buf, sizeof buf, "s %.3g", g.spacing[1]);
        break;
    case PairKind::Circles:
        std::snprintf(buf, sizeof buf, "+-%.3g", g.shift);
        break;
    }
    return buf;
}

int64_t memberKey(const Geometry& g, int layer, double index, double x, double y) {
    const int64_t n = std::max<int64_t>(firstMember(g), std::llround(index));
    int branch = 0;
    if (g.kind == PairKind::Hyperbolas)
        branch = std::abs(x) > std::abs(y) ? (x > 0 ? 0 : 1) : (y > 0 ? 2 : 3);
    return (n * 4 + branch) * 2 + layer;
}

long memberCount(const Geometry& g, int, double lo, double hi) {
    if (!(lo <= hi)) return 0;
    const double from = std::max<double>(firstMember(g), std::ceil(lo));
    return std::max(0L, long(std::floor(hi) - from) + 1);
}

void MemberTally::add(int64_t key) {
    for (auto& [k, c] : counts_)
        if (k == key) {
            ++c;
            return;
        }
    counts_.push_back({key, 1});
}

double MemberTally::over(double samples) const {
    double clear = 1;
    for (const auto& kc : counts_) clear *= 1 - kc.second / samples;
    return 1 - clear;
}

std::vector<double> drawWithCairo(const Geometry& g, double zoom, int width, int height) {
    cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
    cairo_t* cr = cairo_create(surface);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    // World to device: y up, the origin in the middle, zoom pixels a unit (the scene's size
    // is the image's, so the fitted pixel is 1 / zoom).
    cairo_translate(cr, width / 2.0, height / 2.0);
    cairo_scale(cr, zoom, -zoom);
    // Its best: the finest antialiasing, and curves flattened to a hundredth of a pixel.
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_BEST);
    cairo_set_tolerance(cr, 0.01);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_operator(cr, CAIRO_OPERATOR_OVER);
    cairo_set_line_width(cr, g.stroke);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_MITER); // the field's polygon strokes are mitered
    const double h = g.stroke / 2, pixel = 1 / zoom;
    const double reach = std::hypot(width, height) / 2 / zoom + g.stroke; // past every corner
    const double half = std::max(width, height) / 2.0 / zoom;
    auto stroke = [&] { cairo_stroke(cr); };
    for (int l = 0; l < 2; ++l) {
        const double s = g.spacing[l];
        switch (g.kind) {
        case PairKind::LinesRotated:
        case PairKind::LinesPitch: {
            const double a = turn(g, l), ux = std::cos(a), uy = std::sin(a);
            for (long n = long(std::floor(-reach / s)); n * s <= reach; ++n) {
                cairo_move_to(cr, n * s * ux - reach * uy, n * s * uy + reach * ux);
                cairo_line_to(cr, n * s * ux + reach * uy, n * s * uy - reach * ux);
                stroke();
            }
            break;
        }
        case PairKind::Circles: {
            const double cx = l == 0 ? -g.shift : g.shift;
            cairo_arc(cr, cx, 0, h, 0, 2 * kPi); // member 0, a point: a disc of radius t/2
            cairo_fill(cr);
            for (long n = 1; n * s <= reach + std::abs(cx); ++n) {
                cairo_new_sub_path(cr);
                cairo_arc(cr, cx, 0, n * s, 0, 2 * kPi);
                cairo_close_path(cr);
                stroke();
            }
            break;
        }
        case PairKind::Hexagons: {
            const double a = turn(g, l);
            polygon(cr, h, a); // member 0, a point: the hexagon of apothem t/2
            cairo_fill(cr);
            for (long n = 1; n * s <= reach; ++n) {
                polygon(cr, n * s, a);
                stroke();
            }
            break;
        }
        case PairKind::Hyperbolas:
            // |x^2 - y^2| <= half^2 over the frame: members to c = half (and a stroke).
            for (long n = 1; n * s <= half + g.stroke; ++n)
                for (int branch = 0; branch < 4; ++branch) {
                    hyperbolaBranch(cr, n * s, branch, reach, pixel);
                    stroke();
                }
            break;
        }
    }
    cairo_surface_flush(surface);
    if (cairo_status(cr) != CAIRO_STATUS_SUCCESS)
        throw std::runtime_error(cairo_status_to_string(cairo_status(cr)));
    const unsigned char* data = cairo_image_surface_get_data(surface);
    const int stride = cairo_image_surface_get_stride(surface);
    std::vector<double> ink(size_t(width) * height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            uint32_t px;
            std::copy_n(data + size_t(y) * stride + 4 * size_t(x), 4,
                        reinterpret_cast<unsigned char*>(&px));
            ink[size_t(y) * width + x] = 1 - ((px >> 16) & 0xff) / 255.0; // red
        }
    cairo_destroy(cr);
    cairo_surface_destroy(surface);
    return ink;
}

Stats frameStats(const std::vector<double>& image, int width, int margin) {
    double sum = 0, sq = 0;
    long n = 0;
    for (int y = margin; y < width - margin; ++y)
        for (int x = margin; x < width - margin; ++x) {
            const double v = image[size_t(y) * width + x];
            sum += v;
            sq += v * v;
            ++n;
        }
    if (n == 0) return {NAN, NAN};
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sq / n - mean * mean))};
}

std::vector<double> gaussianBlur(const std::vector<double>& image, int width, double sigma) {
    const int r = int(std::ceil(3 * sigma));
    std::vector<double> taps(2 * r + 1);
    double total = 0;
    for (int k = -r; k <= r; ++k) total += taps[k + r] = std::exp(-0.5 * k * k / (sigma * sigma));
    for (double& t : taps) t /= total;
    auto pass = [&](const std::vector<double>& in, bool across) {
        std::vector<double> out(in.size());
        for (int y = 0; y < width; ++y)
            for (int x = 0; x < width; ++x) {
                double v = 0;
                for (int k = -r; k <= r; ++k) {
                    const int xx = across ? std::clamp(x + k, 0, width - 1) : x;
                    const int yy = across ? y : std::clamp(y + k, 0, width - 1);
                    v += taps[k + r] * in[size_t(yy) * width + xx];
                }
                out[size_t(y) * width + x] = v;
            }
        return out;
    };
    return pass(pass(image, true), false);
}

} // namespace moire::exp
