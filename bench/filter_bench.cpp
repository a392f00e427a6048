// The mean filter's frame time against point sampling (docs/filtering.md), measured side by
// side in one run on the same scenes:
//
//   build/bin/moire_filter_bench [--size WxH] [--repeat N] [--interp] [--vulkan] [scene ...]
//
// For each scene (some examples, and the cases the filter is for: fine circles, a fine pair
// whose beat is coarse, walking families past their budget and in closed form), the scene is
// compiled twice, with `filter = point` and with `filter = mean` (CompileOptions::filter), and each
// kernel renders the same frame on the JIT; the fastest of --repeat renders is kept (other work on
// the machine can only add time). The ratio mean / point is the filter's cost on that scene.
// --interp adds the reference interpreter (one render each: it is slow), --vulkan the GPU
// where a device is present.
#include "bench/BenchScenes.h"
#include "compiler/backend/Backend.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "runtime/output/Render.h"

#include <cstdio>
#include <fmt/format.h>
#include <memory>
#include <optional>

using namespace moire;
using bench::Scene;

namespace {

// The scenes the filter is for, written here so the benchmark needs no files of its own.
std::vector<Scene> filterScenes() {
    std::vector<Scene> out;
    for (const char* name : {"two_rings", "fork_grating", "counter_spirals", "hyperbolae"})
        out.push_back(
            bench::sceneFile(std::string(MOIRE_SOURCE_DIR "/examples/") + name + ".moire"));
    // Hyperbolas 0.25 apart, 0.05 wide, 4 a pixel: beside their asymptotes the members crowd
    // into the fold without end, read in parts by P = (phi / s)^2 (FoldMean.h).
    out.push_back({"hyperbolas into the fold", "hyperbola_fold.moire",
                   "layer a { family = hyperbola; spacing = 0.25; stroke = 0.05 }\n"});
    // Circles 0.7 apart, 0.1 wide, at a pixel a world unit: 1.43 members a pixel everywhere.
    out.push_back({"fine circles", "fine_circles.moire",
                   "layer a { family = circles; spacing = 0.7; stroke = 0.1 }\n"});
    // Two line families 0.6 and 0.62 apart at 1.5 degrees: members finer than pixels, a
    // beat tens of pixels wide.
    out.push_back({"fine pair", "fine_pair.moire",
                   "layer a { family = lines; spacing = 0.6; stroke = 0.15 }\n"
                   "layer b { family = lines; spacing = 0.62; stroke = 0.15; "
                   "rotation = 1.5deg }\n"});
    // Two square lattices of edges 0.6 apart, one turned 4 degrees: every line finer than a
    // pixel, each beating with the other grid's (FineUnion.h, strands); and a resolved
    // triangle lattice under lines, whose lines meet as strokes (StrokePairs.h).
    out.push_back({"two fine grids", "lattice_pair.moire",
                   "layer a { family = square_lattice; spacing = 0.6; stroke = 0.12; edges = 1 }\n"
                   "layer b { family = square_lattice; spacing = 0.6; stroke = 0.12; edges = 1; "
                   "rotation = 4deg }\n"});
    // Two honeycombs' dots beating (LatticeUnion.h): their overlap sampled over the pixel.
    out.push_back({"two fine dot screens", "dot_screens.moire",
                   "layer a { family = hex_lattice; spacing = 0.35; stroke = 0.2 }\n"
                   "layer b { family = hex_lattice; spacing = 0.35; stroke = 0.2; "
                   "rotation = 3deg }\n"});
    // Two honeycombs' edges beating (LatticeUnion.h): their cells' overlap over the pixel.
    out.push_back({"two fine honeycombs", "honeycomb_pair.moire",
                   "layer a { family = hex_lattice; spacing = 0.35; stroke = 0.1; edges = 1 }\n"
                   "layer b { family = hex_lattice; spacing = 0.35; stroke = 0.1; edges = 1; "
                   "rotation = 3deg }\n"});
    // A honeycomb's edges about a cell a pixel: the paper its strokes leave over the pixel,
    // the hexagon about the pixel's centre and its six neighbours (HoneycombInPixel.h).
    out.push_back({"honeycomb about a pixel", "honeycomb_pixel.moire",
                   "layer a { family = hex_lattice; spacing = 1; stroke = 0.2; edges = 1; "
                   "rotation = 7deg }\n"});
    // A triangle lattice's edges with its rows about a pixel apart, and resolved: the paper
    // its shrunk triangles leave over the pixel where two of its families' strokes reach it
    // (TriangleInPixel.h), from the 3 x 3 cells about the pixel's and the 2 x 2 nearest it.
    for (const char* spacing : {"1.2", "4"})
        out.push_back({std::string("triangle edges, ") + spacing,
                       std::string("triangle_edges_") + spacing + ".moire",
                       std::string("layer a { family = triangle_lattice; spacing = ") + spacing +
                           "; stroke = " + (spacing[0] == '1' ? "0.3" : "0.6") +
                           "; edges = 1; rotation = 10deg }\n"});
    // A honeycomb's edges under fine lines near a row of its centres (LatticeUnion.h): the
    // hexagons' paper less the lines' strokes across them, at 2 x 2 taps.
    out.push_back({"honeycomb under fine lines", "honeycomb_lines.moire",
                   "layer a { family = hex_lattice; spacing = 0.4; stroke = 0.08; edges = 1 }\n"
                   "layer b { family = lines; spacing = 0.6; stroke = 0.1; angle = 32deg }\n"});
    // A family given by its distance (DistanceFamily.h): rings 0.7 apart (a pixel of every
    // frame read in parts), and 3 apart (the parts only where a ring's stroke meets a ridge).
    for (const char* spacing : {"0.7", "3"})
        out.push_back({std::string("distance rings, ") + spacing,
                       std::string("distance_rings_") + spacing + ".moire",
                       std::string("family rings { distance = abs(r - spacing * round(r / "
                                   "spacing)) }\nlayer a { family = rings; spacing = ") +
                           spacing + "; stroke = " + (spacing[0] == '0' ? "0.1" : "0.8") + " }\n"});
    // Dots given by their distance, 0.7 apart: every pixel in 8 x 8 parts, each fitting its
    // dot's edge's curvature from its neighbours' normals.
    out.push_back({"distance dots, 0.7", "distance_dots.moire",
                   "family dots { distance = hypot(x - spacing * round(x / spacing), y - spacing * "
                   "round(y / spacing)) }\nlayer a { family = dots; spacing = 0.7; stroke = 0.3; "
                   "rotation = 10deg }\n"});
    // Members given by their distance finer than the 8 x 8 parts: dots 0.15 and 0.05 apart,
    // read as a dot screen (DistanceDots.h: two rays out of a dot's cell, nine looks at its
    // edge and three at its cell, in place of 34 rays by their tubes), and a grid's lines, by
    // its two ways in closed form (DistanceGrid.h).
    out.push_back({"distance dots, 0.15", "distance_dots_fine.moire",
                   "family dots { distance = hypot(x - spacing * round(x / spacing), y - spacing * "
                   "round(y / spacing)) }\nlayer a { family = dots; spacing = 0.15; stroke = 0.07; "
                   "rotation = 10deg }\n"});
    out.push_back(
        {"distance dots, 0.05", "distance_dots_finer.moire",
         "family dots { distance = hypot(x - spacing * round(x / spacing), y - spacing * "
         "round(y / spacing)) }\nlayer a { family = dots; spacing = 0.05; stroke = 0.023; "
         "rotation = 10deg }\n"});
    out.push_back({"distance grid, 0.15", "distance_grid_fine.moire",
                   "family grid { distance = min(abs(x - spacing * round(x / spacing)), abs(y - "
                   "spacing * round(y / spacing))) }\nlayer a { family = grid; spacing = 0.15; "
                   "stroke = 0.03; rotation = 10deg }\n"});
    // A grid given by its distance under a phase family's lines turned 3 degrees off one of
    // its ways, both 0.2 apart: the grid's two ways beat with the lines as a lattice's do
    // (FineUnion.cpp, strandCorrelation).
    out.push_back({"distance grid beating, 0.2", "distance_grid_beat.moire",
                   "family grid { distance = min(abs(x - spacing * round(x / spacing)), abs(y - "
                   "spacing * round(y / spacing))) }\nlayer a { family = grid; spacing = 0.2; "
                   "stroke = 0.04; rotation = 10deg }\nlayer b { family = lines; spacing = 0.2; "
                   "stroke = 0.05; rotation = 13deg }\n"});
    // Lines three ways given by their distance, 0.15 apart (the triangle lattice's lines),
    // read in closed form with the three's excess over independent inks (DistanceGrid.h).
    out.push_back({"distance lines three ways, 0.15", "distance_three_ways.moire",
                   "family tri {\n let v = 0.5 * x + 0.8660254037844386 * y\n let w = 0.5 * x - "
                   "0.8660254037844386 * y\n distance = min(abs(x - spacing * round(x / "
                   "spacing)), min(abs(v - spacing * round(v / spacing)), abs(w - spacing * "
                   "round(w / spacing))))\n}\nlayer a { family = tri; spacing = 0.15; stroke = "
                   "0.03; rotation = 10deg }\n"});
    // Dots given by their distance under a phase family's lines turned 3 degrees off their
    // rows, both 0.2 apart: the screen read by its lattice beats with the lines as a
    // lattice's dots do (LatticeUnion.h, dotLineCorrelation).
    out.push_back({"distance dots beating, 0.2", "distance_dots_beat.moire",
                   "family dots { distance = hypot(x - spacing * round(x / spacing), y - spacing * "
                   "round(y / spacing)) }\nlayer a { family = dots; spacing = 0.2; stroke = 0.1; "
                   "rotation = 10deg }\nlayer b { family = lines; spacing = 0.2; stroke = 0.05; "
                   "rotation = 13deg }\n"});
    // Rings given by their distance about a lattice's points, 0.15 apart (five a pixel), radius
    // 0.045: read as the difference of two dot screens (DistanceRings.h), where the tubes read
    // 34 rays a pixel.
    const std::string latticeRings =
        "family rings { distance = abs(hypot(x - spacing * round(x / spacing), y - spacing * "
        "round(y / spacing)) - 0.3 * spacing) }\nlayer a { family = rings; spacing = 0.15; "
        "stroke = 0.03; rotation = 10deg }\n";
    out.push_back(
        {"distance rings on a lattice, 0.15", "distance_rings_lattice.moire", latticeRings});
    // The same rings under lines 3 degrees off: the rings' screen laid on the lines in the
    // union of fine layers, as the outer discs' screen less the inner ones' (LatticeUnion.h).
    out.push_back({"distance rings on a lattice with lines", "distance_rings_lines.moire",
                   latticeRings + "layer b { family = lines; spacing = 0.15; stroke = 0.04; "
                                  "rotation = 13deg }\n"});
    // Two rings given by their distance, 0.2 and 0.21 apart about one centre: each crowd's
    // index read from its parts' normals and the centre's ray, and the pair's beat in closed
    // form (DistanceFamily.h, runs; FineUnion.h).
    out.push_back({"distance rings beating, 0.2", "distance_rings_beat.moire",
                   "family rings { distance = abs(r - spacing * round(r / spacing)) }\n"
                   "layer a { family = rings; spacing = 0.2; stroke = 0.05; origin = (30, 10) }\n"
                   "layer b { family = rings; spacing = 0.21; stroke = 0.06; origin = (30, 10) "
                   "}\n"});
    // Fine lines (1.7 a pixel) under resolved circles 5 apart: the lines' members meet each
    // circle's stroke as periodic strokes (StrokePairs.h, stripesCovariance) wherever the
    // circle crosses a pixel.
    out.push_back({"fine lines under circles", "crowded_resolved.moire",
                   "layer a { family = lines; spacing = 0.6; stroke = 0.2; rotation = 10deg }\n"
                   "layer b { family = circles; spacing = 5; stroke = 1.2 }\n"});
    out.push_back({"triangle grid, resolved", "lattice_resolved.moire",
                   "layer a { family = triangle_lattice; spacing = 8; stroke = 1.5; edges = 1 }\n"
                   "layer b { family = lines; spacing = 6; stroke = 1; rotation = 5deg }\n"});
    // A morph across kinds: a square grid of edges to circles, 0.6 apart (crowded: the
    // families' distributions of distance) and 7 apart (resolved: the blend sampled over the
    // pixel), at the change's start (where the morph holds the grid) and half-way, where the
    // crowded form reads the beat of the grid's lines with the circles (MorphBeat.h); the frame
    // one pixel a world unit, as in the tests.
    for (const char* spacing : {"0.6", "7"})
        for (double time : {0.0, 0.5}) {
            std::string name = std::string("morph across kinds, ") + spacing;
            if (time > 0) name += ", half-way";
            out.push_back(
                {name, std::string("morph_kinds_") + spacing + ".moire",
                 std::string("scene { size = (1920, 1080) }\ntiming change { period = 2 }\n"
                             "layer a { family = morph(change, square_lattice, circles); "
                             "edges = 1; spacing = ") +
                     spacing + "; stroke = " + (spacing[0] == '0' ? "0.12" : "1.5") +
                     "; morph_time = 1 }\n",
                 time});
        }
    // A walking family whose drift equals its spacing, turned half a degree a member: the
    // solver's interval is wider than its budget over most of the frame.
    out.push_back({"walking past budget", "walking_budget.moire",
                   "layer a { family = triangles; spacing = 6; stroke = 1; offset = (6, 0); "
                   "turn = 0.5deg }\n"});
    // Circles drifting by nearly their spacing (7.8 of 8), a degree a member: past the budget
    // their interval turns a few times to many, and several turns' members are drawn.
    out.push_back({"walking circles, turns", "walking_turns.moire",
                   "layer a { family = circles; spacing = 8; stroke = 1.5; offset = (7.8, 0); "
                   "turn = 1deg }\n"});
    // The same at the marginal drift (offset against the facet it faces): its period of 720
    // is past the chains drawn one by one, and the chains that reach each pixel are picked.
    out.push_back({"walking, chains picked", "walking_picked.moire",
                   "layer a { family = triangles; spacing = 8; stroke = 2; offset = (-8, 0); "
                   "turn = 0.5deg }\n"});
    // The same past its budget at a turn of a short period, 10 degrees a member (36 members a
    // full turn): the crowd is drawn chain by chain.
    out.push_back({"walking, 10 deg turn", "walking_period.moire",
                   "layer a { family = hexagons; spacing = 8; stroke = 1.5; offset = (8, 0); "
                   "turn = 10deg }\ncamera { zoom = 0.4 }\n"});
    // Walking families the solver answers in closed form (no turn): circles whose members
    // stand pixels apart (the mean pays the neighbours' test alone), and finer ones, one or
    // two members a pixel (every member within reach drawn as a chain).
    out.push_back({"walking closed form", "walking_closed.moire",
                   "layer a { family = circles; spacing = 8; stroke = 1.5; offset = (3, 1) }\n"});
    out.push_back({"walking closed, fine", "walking_closed_fine.moire",
                   "layer a { family = circles; spacing = 1.6; stroke = 0.3; offset = (0.6, 0.2) "
                   "}\n"});
    return out;
}

// The scene compiled with `filter`, its frame at t = 0 evaluated; null after the diagnostics.
struct Compiled {
    std::unique_ptr<SceneProgram> program;
    FrameValues values;
};
std::optional<Compiled> compileWith(const Scene& s, sema::FilterMode filter, int w, int h) {
    CompileOptions options;
    options.filter = filter;
    CompileResult r = compileScene(s.path, s.text, options);
    if (!r.program) {
        fmt::print(stderr, "{}", r.diagnostics);
        return std::nullopt;
    }
    Compiled out{std::move(r.program), {}};
    FrameRequest req;
    req.width = w;
    req.height = h;
    req.time = s.time;
    std::string diags;
    if (!evaluateFrame(*out.program, req, out.values, diags)) {
        fmt::print(stderr, "{}", diags);
        return std::nullopt;
    }
    return out;
}

// The fastest render of each kernel on `backend`, in ms: {point, mean}.
std::pair<double, double> timeBoth(Backend& backend, const Compiled& point, const Compiled& mean,
                                   int repeat) {
    auto p = backend.compile(point.program->kernel);
    auto m = backend.compile(mean.program->kernel);
    KernelFrame fp{point.values.uniforms.data(), point.values.width, point.values.height};
    KernelFrame fm{mean.values.uniforms.data(), mean.values.width, mean.values.height};
    return {bench::bestRender(*p, fp, repeat) * 1e3, bench::bestRender(*m, fm, repeat) * 1e3};
}

} // namespace

int main(int argc, char** argv) {
    int width = 1920, height = 1080, repeat = 5;
    bool withInterp = false, withVulkan = false;
    std::vector<Scene> scenes;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (bench::sizeOrRepeat(argc, argv, i, width, height, repeat))
            continue;
        else if (a == "--interp")
            withInterp = true;
        else if (a == "--vulkan")
            withVulkan = true;
        else
            scenes.push_back(bench::sceneFile(a));
    }
    if (scenes.empty()) scenes = filterScenes();

    std::unique_ptr<Backend> jit = makeBackend("jit"), interp, vulkan;
    if (withInterp) interp = makeBackend("interp");
    if (withVulkan) {
        try {
            vulkan = makeBackend("vulkan");
        } catch (const BackendError& e) {
            fmt::print("no Vulkan: {}\n", e.what());
        }
    }
    fmt::print("moire filter benchmark: {}x{}, best of {}, ms a frame\n\n", width, height, repeat);
    fmt::print("{:<22} {:>10} {:>10} {:>7}", "scene", "jit point", "jit mean", "ratio");
    if (interp) fmt::print(" {:>10} {:>10} {:>7}", "int point", "int mean", "ratio");
    if (vulkan) fmt::print(" {:>10} {:>10} {:>7}", "vk point", "vk mean", "ratio");
    fmt::print("\n");
    for (const Scene& s : scenes) {
        auto point = compileWith(s, sema::FilterMode::Point, width, height);
        auto mean = compileWith(s, sema::FilterMode::Mean, width, height);
        if (!point || !mean) return 1;
        auto [jp, jm] = timeBoth(*jit, *point, *mean, repeat);
        fmt::print("{:<22} {:>10.2f} {:>10.2f} {:>6.2f}x", s.name, jp, jm, jm / jp);
        if (interp) {
            auto [ip, im] = timeBoth(*interp, *point, *mean, 1); // slow: once is enough
            fmt::print(" {:>10.1f} {:>10.1f} {:>6.2f}x", ip, im, im / ip);
        }
        if (vulkan) {
            auto [vp, vm] = timeBoth(*vulkan, *point, *mean, repeat);
            fmt::print(" {:>10.2f} {:>10.2f} {:>6.2f}x", vp, vm, vm / vp);
        }
        fmt::print("\n");
        std::fflush(stdout);
    }
    fmt::print("\nratio: the mean filter's frame time over point sampling's, the same scene and\n"
               "frame, rendered one after the other in this run.\n");
    return 0;
}
