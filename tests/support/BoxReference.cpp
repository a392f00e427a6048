#include "tests/support/BoxReference.h"

#include <cmath>

namespace moire::test {

std::vector<double> boxReference(int width, int height, double zoom,
                                 const std::function<bool(double, double)>& inked,
                                 RankOneLattice lattice) {
    std::vector<double> out(size_t(width) * height);
    for (int py = 0; py < height; ++py)
        for (int px = 0; px < width; ++px) {
            int hits = 0;
            for (int j = 0; j < lattice.n; ++j) {
                const double sx = (j + 0.5) / lattice.n;
                const double t = j * lattice.g + 0.5;
                const double sy = t - std::floor(t);
                const double x = (px + sx - 0.5 * width) / zoom;
                const double y = (0.5 * height - py - sy) / zoom;
                hits += inked(x, y);
            }
            out[size_t(py) * width + px] = double(hits) / lattice.n;
        }
    return out;
}

InkError inkError(const Image& frame, const std::vector<double>& reference) {
    double sq = 0.0, ink = 0.0, exact = 0.0;
    for (int py = 0; py < frame.height; ++py)
        for (int px = 0; px < frame.width; ++px) {
            const double got = 1.0 - frame.at(px, py, 0);
            const double want = reference[size_t(py) * frame.width + px];
            sq += (got - want) * (got - want);
            ink += got;
            exact += want;
        }
    const double n = double(frame.width) * frame.height;
    return {std::sqrt(sq / n), ink / n, exact / n};
}

} // namespace moire::test
