// Fig. 17 of the spec (§9.6): two subsamplings of the same cost and different structure. One
// scene with the budget forced to 64, so that the scan strides while the field is still
// legible, solved with the stride anchored to each pixel's own n_lo and to the global index
// lattice (multiples of the stride). Both spend the same evaluations and keep about the same
// ink; what differs is structure, measured as the number of connected stroke fragments
// (8-connected components of the pixels over half ink).
//
//   build/bin/experiments/stride_anchor [--quick] [--images DIR]
//
// --images DIR writes the three panels (exact, pixel-anchored, lattice-anchored) as PNGs.
#include "experiments/Harness.h"
#include "experiments/WalkingSettings.h"
#include "runtime/output/ImageIO.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fmt/format.h>
#include <string>
#include <vector>

using namespace moire;
using namespace moire::exp;

namespace {

// The scene: walking squares, spacing 6, drifting by (3, 1) (m = s / 2) with a turn of 0.3
// degrees: over the crop the interval is around a hundred members, so B = 64 strides by 2
// while the rings are still a few pixels apart.
WalkSetting scene() {
    WalkSetting s;
    s.shape = 2; // square
    s.spacing = 6;
    s.offsetX = 3;
    s.offsetY = 1;
    s.turnDeg = 0.3;
    s.zoom = 1;
    return s;
}

struct Panel {
    std::vector<double> cover;
    double ink = 0, evaluations = 0;
    int fragments = 0;
};

// Connected components of the pixels over half ink, 8-connected.
int fragments(const std::vector<double>& cover, int w, int h) {
    std::vector<int> label(cover.size(), 0), stack;
    int count = 0;
    for (int start = 0; start < w * h; ++start) {
        if (cover[start] <= 0.5 || label[start]) continue;
        ++count;
        label[start] = count;
        stack.push_back(start);
        while (!stack.empty()) {
            const int i = stack.back();
            stack.pop_back();
            const int x = i % w, y = i / w;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                    const int j = ny * w + nx;
                    if (cover[j] > 0.5 && !label[j]) {
                        label[j] = count;
                        stack.push_back(j);
                    }
                }
        }
    }
    return count;
}

Panel solve(const lower::WalkingVariant& v, int x0, int y0, int w, int h) {
    WalkingKernel kernel(scene().shape, v);
    kernel.set(scene());
    Panel p;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Solved s = kernel.at(x0 + x + 0.5, y0 + y + 0.5);
            p.cover.push_back(coverageOf(s.distance, kernel.band()));
            p.ink += p.cover.back();
            p.evaluations += s.evaluations;
        }
    p.ink /= w * h;
    p.evaluations /= w * h;
    p.fragments = fragments(p.cover, w, h);
    return p;
}

void writePanel(const std::string& path, const Panel& p, int w, int h) {
    Image img(w, h, 4);
    for (int i = 0; i < w * h; ++i) {
        const float v = static_cast<float>(1.0 - p.cover[i]); // dark ink on white
        for (int c = 0; c < 3; ++c) img.pixels[4 * i + c] = v;
        img.pixels[4 * i + 3] = 1.0f;
    }
    writeImage(path, img);
}

} // namespace

int main(int argc, char** argv) {
    std::string images;
    std::vector<char*> rest{argv[0]};
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--images") == 0 && i + 1 < argc)
            images = argv[++i];
        else
            rest.push_back(argv[i]);
    }
    const Options opt = parseOptions(static_cast<int>(rest.size()), rest.data(),
                                     "Fig. 17 of spec §9.6 (--images DIR: write the panels)");
    // A crop of the 1200 x 800 frame to the right of the centre, where the interval is wide.
    const int w = opt.quick ? 120 : 300, h = opt.quick ? 80 : 200;
    const int x0 = 800, y0 = 300;
    lower::WalkingVariant exactV, pixelV, latticeV;
    exactV.budget = 131072; // the whole capped span at stride 1
    pixelV.budget = latticeV.budget = 64;
    pixelV.latticeAnchored = false;
    const Panel exact = solve(exactV, x0, y0, w, h);
    const Panel pixel = solve(pixelV, x0, y0, w, h);
    const Panel lattice = solve(latticeV, x0, y0, w, h);

    printTitle(fmt::format("stride_anchor: Fig. 17, a {}x{} crop, budget forced to 64", w, h));
    printRow("evaluations per pixel: pixel-anchored", "33",
             fmt::format("{:.1f}", pixel.evaluations));
    printRow("evaluations per pixel: lattice-anchored", "33",
             fmt::format("{:.1f}", lattice.evaluations));
    printRow("evaluations per pixel: exact (B = 131072)", "-",
             fmt::format("{:.1f}", exact.evaluations));
    printRow("ink: exact", "0.489", fmt::format("{:.3f}", exact.ink));
    printRow("ink: pixel-anchored", "0.216", fmt::format("{:.3f}", pixel.ink));
    printRow("ink: lattice-anchored", "0.216", fmt::format("{:.3f}", lattice.ink));
    printRow("stroke fragments: exact", "-", fmt::format("{}", exact.fragments));
    printRow("stroke fragments: pixel-anchored", "shattered", fmt::format("{}", pixel.fragments));
    printRow("stroke fragments: lattice-anchored", "whole lines",
             fmt::format("{}", lattice.fragments));

    if (!images.empty()) {
        writePanel(images + "/fig17-exact.png", exact, w, h);
        writePanel(images + "/fig17-pixel-anchored.png", pixel, w, h);
        writePanel(images + "/fig17-lattice-anchored.png", lattice, w, h);
        std::printf("wrote %s/fig17-{exact,pixel-anchored,lattice-anchored}.png\n", images.c_str());
    }
    // Same cost and ink within a tenth of each other; many more fragments pixel-anchored
    // (the full crop: over four times; the quick one, over 1.5 times).
    const bool sameCost =
        std::fabs(pixel.evaluations - lattice.evaluations) <= 0.1 * lattice.evaluations;
    const bool sameInk = std::fabs(pixel.ink - lattice.ink) <= 0.1 * lattice.ink;
    const bool strided = lattice.ink < exact.ink;
    return verdict(sameCost && sameInk && strided && 2 * pixel.fragments > 3 * lattice.fragments,
                   "the two anchors should cost and ink alike, both under the exact field, with "
                   "over twice the fragments when anchored at each pixel");
}
