// The mean ink of a family given by its distance whose members are finer than the parts the
// pixel is read in (docs/filtering.md, "Families given by their distance").
//
// Every point of the plane lies on one ray: the normal from its nearest member's nearest point
// (its foot), which runs straight until another member is as near (the ridge, M along it). The
// rays from a stretch of member sweep a tube whose width grows along it by (1 + kappa0 s), kappa0
// the member's curvature at the foot (a point member: kappa0 infinite, the width grows as s); so
// the share of a ray's tube within h of its member is
//     g = (2h + kappa0 h^2) / (2M + kappa0 M^2)   (h < M; 1 where the whole ray is inked),
// h^2 / M^2 for a point, h / M for a straight member. A point drawn at random from the plane
// falls on a ray with chance its tube's area, so the mean of g over such points is the share of
// the plane that is inked, exactly, whatever the members' shapes and spacing: the sum over the
// tubes of their areas times their shares. Over a pixel that holds many members the pixel is
// many whole tubes, and the mean of g over points spread across it is its mean ink. Unlike the
// samples' own ink (1 or 0, which a lattice of members aliases with), g varies only with the
// ray's length: it is the same at every point of a ray of parallel curves.
//
// Each sample finds its ridge along its normal by probing there: a probe reads the same member
// while its foot is the sample's, and past the ridge it reads another, which, taken as bending
// as the sample's own member, puts the ridge where the two are as near (ridgeModel in the .cpp:
// exact for dots, parallel curves and a grid's crossing lines), in a bracket kept by the probes.
// kappa0 comes first, from two probes a small step either side along the level set: the normals
// of parallel curves meet at the centre of curvature, so their turn says the level set's
// curvature kappa_t there, and kappa0 = kappa_t / (1 - kappa_t t0), t0 the sample's distance.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/lower/DistanceReading.h"

namespace moire::lower {

// Samples over the pixel: a Fibonacci lattice of 34 points (step 21), moved from pixel to pixel
// (distanceTubesMean), visited 13 at a time so that the first few spread over the pixel. (An
// 8 x 8 grid of 64 cost twice as much for the same figures, and lined up with a grid's lines
// 1/8 of a pixel apart: 0.031 RMSE.)
constexpr int kTubeSamples = 34, kLatticeStep = 21, kVisitStep = 13;
// The parts the rays are measured against (DistanceFamily.cpp's finer parts).
constexpr int kDistanceFineTaps = 8;
// How far along its normal a sample looks for its ridge, in fine parts' sides: beyond, the ray
// is long enough for the parts to read its member.
constexpr double kTubeReach = 3.0;
// Where the pixel's members stand further than this many fine parts' sides from points of the
// pixel on average (DistanceFamily.cpp reads that from its 4 x 4 parts, each distance held to
// kTubeReach), it is not read by its tubes. A ray runs past its sample, on average half again
// its distance for a dot's (which counts half, below) and twice for a line's (which counts 1.5
// times), so the rays' mean length as the parts see it is past the hand-over's end (0.95)
// there.
constexpr double kTubeGate = 1.5;

// `mean`: the mean of g over the pixel's samples. `crowded`: how far the pixel is read by its
// tubes rather than in parts, 0 to 1: 1 where the samples' rays are short against the fine
// parts (their mean length under 0.7 of a part's side, a dot's ray counted half and a straight
// member's 1.5 times: from about 3.3 dots, 5.7 rows of a grid or 8.5 lines a pixel), 0 where
// they are long (past 0.95: under 2.4, 4.2 and 6.3), where the parts read the members' edges
// and the tubes' share is off by the members the pixel cuts.
struct TubeEstimate {
    ir::ValueId mean, crowded;
};
// The ray through p (a point of the pixel, read there as r): its length from its member's foot
// to the ridge, looked for up to `cap` along it (`cap` where it runs further), and kappa0, the
// member's curvature at the foot (0 where the ray runs past the cap); with `next`, how far
// along the normal the next member's foot stands from its own, read by a probe past the ridge
// (twice the ray where none is read). Each of the tubes' samples reads one; the index a crowd
// of parallel members runs by reads the pixel centre's (DistanceFamily.cpp: its spacing).
// `across`, with `next`: where the probe past the ridge read a member whose normal is not
// parallel to the ray's (a grid's crossing line, not the next of the ray's own), and that
// probe's place, a point whose nearest member is that one.
struct RayLength {
    ir::ValueId ridge, kappa0;
    ir::ValueId next = ir::kNoValue, across = ir::kNoValue;
    PixelPoint acrossAt{ir::kNoValue, ir::kNoValue};
};
RayLength rayThrough(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                     const Reading& r, PixelPoint p, ir::ValueId cap, bool next = false);

TubeEstimate distanceTubesMean(ir::Builder& b, const DistanceAt& at, ir::ValueId halfWidth,
                               const PixelFootprint& pixel);

} // namespace moire::lower
