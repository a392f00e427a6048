// Table 3 (spec §9.2): the walking solver's cost per megapixel of solver work, for Sweep (a
// fixed neighbourhood, no certificate), Loose (Theorem 4 with ||delta|| for the drift
// constant) and Window (the shipped method), on the CPU backends: the JIT scalar (a pixel a
// step) and in its lanes, one thread. The paper's figures are GPU pass times (Apple
// metal-3); ours are CPU, so the columns to compare are the ratios between solvers.
//
//   build/bin/experiments/table3_cost [--quick]
//
// The full run times 1200 x 800 frames (0.96 Mpixel, the paper's grid) per row and solver,
// the fastest of three, and counts the radius evaluations a pixel with the interpreter on
// every 8th pixel of every 8th row. --quick renders 120 x 80 once and asserts on the counts
// only, never on a clock: Window looks at no more members than Sweep on every row but the
// marginal drift, where it spends its budget on purpose.
#include "experiments/Harness.h"
#include "experiments/WalkingTiming.h"

#include <cstdio>
#include <vector>

using namespace moire;
using namespace moire::exp;

namespace {

struct Row {
    WalkingScene scene;
    double paper[3]; // Sweep, Loose, Window: ms per Mpx on the paper's GPU
    bool marginal = false;
};

// The paper's 14 rows in our parameters: spacing 8, stroke 1.5, a turn of 1.2 degrees
// (0.4 near the spacing), an offset of (1.5, 0.6) where the row has one, zoom 1 or 0.15. Near
// the spacing -delta points at the triangle's corner: ||delta|| = 0.95 s, m = 0.475 s. The
// marginal row's -delta is a hexagon facet's normal, so m = ||delta|| = s.
std::vector<Row> rows() {
    auto layer = [](const char* family, double zoom, const char* walk) {
        std::string out = zoom != 1.0 ? "camera { zoom = " + std::to_string(zoom) + " }\n" : "";
        return out + "layer { family = " + family + "; spacing = 8; stroke = 1.5; " + walk + " }";
    };
    const char* rot = "turn = 1.2deg";
    const char* both = "offset = (1.5, 0.6); turn = 1.2deg";
    const char* near = "offset = (7.6, 0); turn = 0.4deg";
    return {
        {{"Circle, rotation + offset, zoom 1", layer("circles", 1, both)}, {9.84, 0.34, 0.37}},
        {{"Circle, rotation + offset, zoom 0.15", layer("circles", 0.15, both)},
         {14.82, 1.19, 1.22}},
        {{"Square, rotation, zoom 1", layer("squares", 1, rot)}, {8.56, 0.27, 0.30}},
        {{"Square, rotation + offset, zoom 0.15", layer("squares", 0.15, both)},
         {12.93, 0.87, 0.88}},
        {{"Square, offset only, zoom 1", layer("squares", 1, "offset = (1.5, 0.6)")},
         {0.95, 0.95, 0.18}},
        {{"Triangle, rotation, zoom 1", layer("triangles", 1, rot)}, {13.14, 0.48, 0.37}},
        {{"Triangle, rotation, zoom 0.15", layer("triangles", 0.15, rot)}, {18.44, 1.45, 1.03}},
        {{"Triangle, rotation + offset, zoom 1", layer("triangles", 1, both)}, {15.64, 0.73, 0.53}},
        {{"Triangle, rotation + offset, zoom 0.15", layer("triangles", 0.15, both)},
         {26.13, 2.67, 1.85}},
        {{"Hexagon, rotation + offset, zoom 0.15", layer("hexagons", 0.15, both)},
         {23.44, 2.23, 1.83}},
        {{"Nonagon, rotation + offset, zoom 0.15",
          layer("ngon", 0.15, "sides = 9; offset = (1.5, 0.6); turn = 1.2deg")},
         {22.66, 2.06, 2.25}},
        {{"Offset near spacing, zoom 1", layer("triangles", 1, near)}, {40.34, 2.58, 1.68}},
        {{"Offset near spacing, zoom 0.15", layer("triangles", 0.15, near)}, {45.00, 7.17, 6.10}},
        {{"Marginal drift m = s, rotated, zoom 1",
          layer("hexagons", 1, "offset = (-8, 0); turn = 0.4deg")},
         {63.00, 30.24, 19.26},
         true},
    };
}

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, v >= 100 ? "%.0f" : v >= 10 ? "%.1f" : "%.2f", v);
    return buf;
}

} // namespace

int main(int argc, char** argv) {
    const Options opt = parseOptions(argc, argv, "the cost table of spec §9.2 (Table 3)");
    const int w = opt.quick ? 120 : 1200, h = opt.quick ? 80 : 800;
    const int repeat = opt.quick ? 1 : 3, step = opt.quick ? 2 : 8, lanes = jitLanes();
    const double mpx = w * h * 1e-6;
    using Solver = lower::WalkingVariant::Solver;
    const Solver solvers[] = {Solver::Sweep, Solver::Loose, Solver::Window};

    printTitle("Table 3: ms per Mpx of solver work, Sweep / Loose / Window; paper: GPU, ours: "
               "JIT scalar | JIT " +
               std::to_string(lanes) + " lanes | evaluations a pixel (" + std::to_string(w) + "x" +
               std::to_string(h) + ", one thread)");
    bool ok = true;
    std::string why;
    for (const Row& row : rows()) {
        std::string scalar, inLanes, evals;
        double count[3];
        for (int i = 0; i < 3; ++i) {
            lower::WalkingVariant v;
            v.solver = solvers[i];
            const char* sep = i ? " / " : "";
            scalar += sep + num(jitSeconds(row.scene, v, w, h, 1, repeat) * 1e3 / mpx);
            inLanes += sep + num(jitSeconds(row.scene, v, w, h, lanes, repeat) * 1e3 / mpx);
            count[i] = evaluationsPerPixel(row.scene, v, w, h, step);
            evals += sep + num(count[i]);
        }
        printRow(row.scene.name,
                 num(row.paper[0]) + " / " + num(row.paper[1]) + " / " + num(row.paper[2]),
                 scalar + " | " + inLanes + " | " + evals);
        if (!row.marginal && count[2] > count[0]) {
            ok = false;
            why += " " + row.scene.name;
        }
    }
    return verdict(ok, "Window evaluated the radius more often than Sweep on:" + why);
}
