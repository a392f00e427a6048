#include "runtime/print/Marks.h"

#include <algorithm>
#include <cmath>

namespace moire::print {

namespace {

double px(double mm, double dpi) {
    return mm / kMmPerInch * dpi;
}

// The distance from p to the segment a-b.
double segmentDistance(double px_, double py, const MarkShape& m) {
    const double dx = m.x1 - m.x0, dy = m.y1 - m.y0;
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((px_ - m.x0) * dx + (py - m.y0) * dy) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(px_ - (m.x0 + t * dx), py - (m.y0 + t * dy));
}

// The pixels a shape can touch: its box grown by its half-width and one pixel.
struct Bounds {
    double x0, y0, x1, y1;
};
Bounds boundsOf(const MarkShape& m) {
    const double g = m.halfWidth + 1.0;
    if (m.circle)
        return {m.x0 - m.radius - g, m.y0 - m.radius - g, m.x0 + m.radius + g, m.y0 + m.radius + g};
    return {std::min(m.x0, m.x1) - g, std::min(m.y0, m.y1) - g, std::max(m.x0, m.x1) + g,
            std::max(m.y0, m.y1) + g};
}

float coverageOf(const MarkShape& m, double cx, double cy) {
    const double d = m.circle ? std::fabs(std::hypot(cx - m.x0, cy - m.y0) - m.radius)
                              : segmentDistance(cx, cy, m);
    // A line of width 2 hw covers, of a pixel at distance d from its centre line, about
    // hw + 0.5 - d (clamped): all of it inside, nothing past half a pixel beyond its edge.
    return static_cast<float>(std::clamp(m.halfWidth + 0.5 - d, 0.0, 1.0));
}

} // namespace

std::vector<MarkShape> sheetMarks(const SheetLayout& s, double dpi) {
    std::vector<MarkShape> out;
    if (s.margin <= 0) return out;
    // Lines at least a pixel wide, so that a low resolution still prints them.
    const double hw = std::max(px(kMarkLineMm, dpi), 1.0) * 0.5;
    const double gap = px(kMarkGapMm, dpi);
    const double edge = 1.0; // a pixel clear of the sheet's edge
    auto line = [&](double x0, double y0, double x1, double y1) {
        out.push_back({false, x0, y0, x1, y1, 0.0, hw});
    };
    // Crop marks: each edge of the trim continued outwards from a gap past the bleed to the
    // margin's outer edge, on the line between the trim's pixels (pixel boundaries).
    const double tx[2] = {double(s.trim.x0), double(s.trim.x1)};
    const double ty[2] = {double(s.trim.y0), double(s.trim.y1)};
    const double inner[2][2] = {{double(s.art.x0) - gap, double(s.art.x1) + gap},
                                {double(s.art.y0) - gap, double(s.art.y1) + gap}};
    const double outer[2][2] = {{edge, double(s.width) - edge}, {edge, double(s.height) - edge}};
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            line(tx[i], inner[1][j], tx[i], outer[1][j]); // vertical, above or below
            line(inner[0][i], ty[j], outer[0][i], ty[j]); // horizontal, left or right
        }
    // Registration targets, centred in the margin on the trim's middle lines.
    const double r = px(kTargetRadiusMm, dpi), arm = px(kTargetArmMm, dpi);
    const double mid = s.margin * 0.5;
    const double cx = (s.trim.x0 + s.trim.x1) * 0.5, cy = (s.trim.y0 + s.trim.y1) * 0.5;
    const double centres[4][2] = {
        {cx, mid}, {cx, double(s.height) - mid}, {mid, cy}, {double(s.width) - mid, cy}};
    for (const auto& c : centres) {
        out.push_back({true, c[0], c[1], 0.0, 0.0, r, hw});
        line(c[0] - arm, c[1], c[0] + arm, c[1]);
        line(c[0], c[1] - arm, c[0], c[1] + arm);
    }
    return out;
}

float markCoverage(const SheetLayout& s, const std::vector<MarkShape>& marks, long long x,
                   long long y) {
    if (s.art.contains(x, y) || x < 0 || y < 0 || x >= s.width || y >= s.height) return 0.0f;
    const double cx = x + 0.5, cy = y + 0.5;
    float most = 0.0f;
    for (const MarkShape& m : marks) {
        const Bounds b = boundsOf(m);
        if (cx < b.x0 || cx > b.x1 || cy < b.y0 || cy > b.y1) continue;
        most = std::max(most, coverageOf(m, cx, cy));
    }
    return most;
}

void finishRows(const SheetLayout& s, const std::vector<MarkShape>& marks, const float margin[4],
                long long y, int count, float* rows, size_t stride, int channels) {
    std::vector<float> cover; // the marks' ink along one row, where they cross it
    for (int r = 0; r < count; ++r) {
        const long long row = y + r;
        float* p = rows + static_cast<size_t>(r) * stride;
        auto set = [&](long long x0, long long x1) {
            for (long long x = x0; x < x1; ++x)
                std::copy(margin, margin + 4, p + static_cast<size_t>(x) * channels);
        };
        const bool inArt = row >= s.art.y0 && row < s.art.y1;
        if (!inArt) {
            set(0, s.width);
        } else {
            set(0, s.art.x0);
            set(s.art.x1, s.width);
        }
        const double cy = row + 0.5;
        long long lo = s.width, hi = 0;
        for (const MarkShape& m : marks) {
            const Bounds b = boundsOf(m);
            if (cy < b.y0 || cy > b.y1) continue;
            if (cover.empty()) cover.assign(static_cast<size_t>(s.width), 0.0f);
            const long long x0 = std::max(0LL, static_cast<long long>(std::floor(b.x0)));
            const long long x1 = std::min(s.width, static_cast<long long>(std::ceil(b.x1)) + 1);
            for (long long x = x0; x < x1; ++x) {
                // Never over the artwork, whatever the resolution makes of the measures.
                if (inArt && x >= s.art.x0 && x < s.art.x1) continue;
                float& c = cover[static_cast<size_t>(x)];
                c = std::max(c, coverageOf(m, x + 0.5, cy));
            }
            lo = std::min(lo, x0), hi = std::max(hi, x1);
        }
        for (long long x = lo; x < hi; ++x) {
            float& cov = cover[static_cast<size_t>(x)];
            if (cov <= 0.0f) continue;
            // Black over the pixel, straight alpha: colour c a (1 - cov) / a'.
            float* q = p + static_cast<size_t>(x) * channels;
            const float a = q[3], out = cov + a * (1.0f - cov);
            const float keep = out > 0.0f ? a * (1.0f - cov) / out : 0.0f;
            q[0] *= keep, q[1] *= keep, q[2] *= keep;
            q[3] = out;
            cov = 0.0f;
        }
    }
}

} // namespace moire::print
