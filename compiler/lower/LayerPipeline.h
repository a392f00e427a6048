// The per-pixel maths of a layer, written once as IR-building code (every backend runs it):
//  - the index and distance fields of a phase family (Eq. 5 of the spec, with the
//    gradient from forward-mode AD),
//  - the stroke floor and coverage (Eqs. 4 and 35),
//  - ink-over-paper compositing (§3.4).
#pragma once

#include "compiler/ir/Builder.h"

#include <algorithm>
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace moire::lower {

// A layer's phase sample at the pixel (Eq. 14), for the views that advance every layer's
// index and average (lower/Envelope.h): the signed world distances from the pixel to the
// nearest member (z), to the member after it (up) and to the one before it (down), each
// measured along the index's increase so that advancing the index by a moves every member by
// -a * gap, and a floor for ink that does not slide. A member that does not exist (below a
// family's `first`) is kNoMember away. kNoValue in z: the family gives no sample.
constexpr double kNoMember = 1e30;
// A phase family that starts at member `first` measures that member, from short of it, by the
// fold's estimate (phaseFamilyFields): after an advance a, where index + a < first, the
// distance is at least (lo - a step)(hi - a step) * scale (scale 0 where it does not apply),
// and is exactly that where `exact` (on the fold itself, where Eq. 5 says nothing).
struct FoldSample {
    int first = 0;
    ir::ValueId index, lo, hi, step, scale, exact;
};
// A lattice's index is a pair (spec §3.6, §4.4): advancing it by (du, dv) translates the
// lattice by du and dv of its two generating steps. Finding the nearest point or edge is
// rounding in the lattice's basis, straight-line arithmetic, so a tap re-solves the
// translated lattice exactly: `at(b, du, dv)` emits the distance there. `cell` is the world
// length of one generating step, the lattice's period for the edge's band (Envelope.cpp).
// `dots` is true where the layer draws its points (round strokes), false for its edges.
struct LatticeSample {
    std::function<ir::ValueId(ir::Builder&, ir::ValueId du, ir::ValueId dv)> at;
    ir::ValueId cell = ir::kNoValue;
    ir::ValueId dots = ir::kNoValue;
};
struct MorphSample;
struct PhaseSample {
    ir::ValueId z = ir::kNoValue, up = ir::kNoValue, down = ir::kNoValue, floor = ir::kNoValue;
    std::optional<FoldSample> fold;
    std::optional<LatticeSample> lattice;     // rank two: z is the distance, up and down unused
    std::shared_ptr<const MorphSample> morph; // a morph across kinds: z, up, down unused
};
// A morph across kinds draws mix(d_from, d_to, weight) of two of its members' distances
// (MorphFamily.cpp): advanced, each member advances in its own parameter, and the blend of
// the advanced distances is the layer's. `from` and `to` are the members' positions.
struct MorphSample {
    std::vector<PhaseSample> members;
    ir::ValueId from, to, weight;
};

// What the mean filter reads of a phase family (Prefilter.h): its fractional index, whose
// members sit at the integers and run locally evenly, the index gradient's length per world
// unit and its components, and the first member where the family starts at one. Set by
// phaseFamilyFields and by the pencil (its winding index, with Footprint::edge): a family whose
// members are not that (walking, lattices, morphs, distance families) leaves it unset and is
// drawn from its distance.
struct Footprint {
    ir::ValueId index = ir::kNoValue, grad = ir::kNoValue;
    ir::ValueId gradX = ir::kNoValue, gradY = ir::kNoValue; // the gradient's components
    std::optional<int> first;
    // The world distance from the point to a region the members do not enter (the pencil's
    // open disc), where the periodic sum would count them: where the footprint reaches it,
    // the nearest member's distance mean, as below a first member. kNoValue: none. A family
    // with one is not a phase family to the fine union or the stroke pairs, which read the
    // index alone; they take it as a distance family whose members may crowd.
    ir::ValueId edge = ir::kNoValue;
    // Where the index is not linear across the pixel (a polygon's support function folding
    // along its corners, the circles' centre): how far the pixel's mean stands with `bentMean`,
    // the pixel read in parts, rather than with the closed form of a linear index, 0 to 1
    // (Prefilter.h: bentIndexMean). kNoValue: not read.
    ir::ValueId bent = ir::kNoValue, bentMean = ir::kNoValue;
    // Where the footprint reaches below the first member: the pixel's mean read in parts
    // (Prefilter.h: belowFirstMean). kNoValue: the nearest member's distance mean instead.
    ir::ValueId belowMean = ir::kNoValue;
    // How far the index stands for the members over the pixel, 0 to 1, where it is read from
    // them rather than given (a family given by its distance: CrowdEstimate::runs). The union
    // of fine layers and the lattices' strands take its crowd as that much past resolved
    // (FineUnion.h, unresolved). kNoValue: wholly.
    ir::ValueId trust = ir::kNoValue;
};

// A family's own estimate of the ink its members lay where it cannot resolve them itself (the
// walking solver past its search budget, which strides over the members; a lattice whose
// cells are finer than the pixel, LatticeCrowd.h): `mean`, the pixel's
// mean ink of the stroke as written over the crowd (WalkingDensity.cpp derives it from the
// members' density), and `engaged` in [0, 1], how far it is to be trusted over the drawn
// stroke (0 where the search was exhaustive). Under the mean filter the compose step hands the
// drawn ink over to `mean` by `engaged` (Prefilter.h: crowdInk). kNoValue: the family gives
// none.
struct CrowdEstimate {
    ir::ValueId engaged = ir::kNoValue, mean = ir::kNoValue;
    // How far the nearest member's stroke has stopped standing for the layer's strokes where
    // they meet another layer's (StrokePairs.h), where that is not `engaged`: a honeycomb's
    // edges are measured over the pixel whole up to several rows a pixel, but its nearest
    // stroke is one of the strokes a pixel holds once its rows are a pixel apart. kNoValue:
    // `engaged`.
    ir::ValueId strokesCrowded = ir::kNoValue;
    // Where the family does resolve its members (the walking scan within its budget), the
    // pixel's mean ink of the union of the members' strokes within its reach less the nearest
    // member's own: the compose step adds it to the nearest member's mean (crowdInk), so that
    // members closer than a pixel all count. kNoValue: the family gives none.
    ir::ValueId others = ir::kNoValue;
    // Where `mean` is the union of whole lines laid as independent inks (a square or triangle
    // lattice's edges, LatticeCrowd.h), those lines: each a phase family's footprint with its
    // footprint mean, which the union of fine layers and the stroke pairs correlate with
    // another layer's lines (FineUnion.h, StrokePairs.h). `strandsOn` is where the layer draws
    // them (its edges, not its points). Empty elsewhere.
    std::vector<Footprint> strands;
    std::vector<ir::ValueId> strandMeans;
    ir::ValueId strandsOn = ir::kNoValue;
    // The nearest member's mean ink over the pixel where the family knows its shape better
    // than a stroke across its normal (a lattice's dot, LatticeCrowd.h): the compose step
    // takes it in place of the distance form. kNoValue: the distance form.
    ir::ValueId nearest = ir::kNoValue;
    // The share of the plane within `halfWidth` of a member where the members crowd: the
    // distribution of the distance to the nearest member over a pixel that holds many, which
    // a morph across kinds reads to blend two families' distances (MorphFamily.cpp). Empty
    // where the family gives none.
    std::function<ir::ValueId(ir::Builder&, ir::ValueId halfWidth)> share;
    // A lattice's shape as the union of fine layers reads it, to correlate two lattices by
    // their dots or cells (LatticeUnion.h): set on every lattice whose generators are
    // known.
    struct LatticeShape {
        // The generators, whose whole values offset by each of `sites` are the points, with
        // their gradients per world unit.
        ir::ValueId u, ux, uy, v, vx, vy;
        std::vector<std::array<double, 2>> sites;
        // The shortest vectors of the reciprocal lattice, as (m, n): m grad u + n grad v, each
        // up to its sign (the rows of points that stand closest together).
        std::vector<std::array<int, 2>> shortest;
        ir::ValueId radius; // half the stroke: a dot's radius, an edge's half-width (world)
        ir::ValueId dots;   // a bool: the lattice draws its points, else its edges
        // Where each point is a ring rather than a dot (rings given by their distance,
        // DistanceRings.h): the radius of the disc its stroke leaves inside (0 where it leaves
        // none), the ring being the disc of `radius` less that one. Every closed form of a
        // screen is linear in its dots, so the union reads a ring as the two discs' difference.
        // kNoValue: dots.
        ir::ValueId inner = ir::kNoValue;
        // The paper its edges leave, one cell of the generators' lattice: regions bounded on
        // three directions of lines, m_i . (u, v) <= upper_i and -m_i . (u, v) <= lower_i
        // (either set of bounds absent: unbounded that way), the normals m_i summing to 0
        // (LatticeUnion.h, cellArea). Empty for the square lattice, whose strands stand for it.
        std::array<std::array<double, 2>, 3> normals{};
        double kappa = 0.0; // the area of {m_i . (u, v) <= b_i} over (b_1 + b_2 + b_3)^2
        struct Cell {
            std::optional<std::array<double, 3>> upper, lower;
        };
        std::vector<Cell> cells;
    };
    std::optional<LatticeShape> shape;
    // A family given by its distance whose members crowd and run parallel over the pixel:
    // the index they run by, as a phase family's footprint (members at the integers, the
    // nearest at 0; its `trust` how nearly they run parallel), and the stroke's half-width
    // across them in world units, which the union of fine layers reads to let the family beat
    // with another layer (FineUnion.h; DistanceFamily.h derives it). Unset on other families.
    // Where the members run two or three ways instead, a grid's lines (DistanceGrid.h),
    // `footprint` is the first way's index, `second` the second's and `third` the third's,
    // each a strand of the layer as a lattice's lines are (FineUnion.h), `twoWays` how far
    // that is trusted (0 where they run one way) and `means` each way's mean ink over the
    // pixel. Where `twoWays` is 0, `second` stands for no lines (its trust 0, its gradient too
    // steep for any beat to be slow), and so does `third` where they run two ways.
    // Where the members are dots on a lattice (DistanceDots.h), `screen` is that dot
    // screen's shape, its `dots` true where it is read so, which the union of fine layers
    // correlates as a lattice's dots (LatticeUnion.h); where they are rings about a
    // lattice's points (DistanceRings.h), the rings' screen, its `inner` set.
    struct Runs {
        Footprint footprint;
        ir::ValueId halfWidth = ir::kNoValue;
        Footprint second, third;
        ir::ValueId twoWays = ir::kNoValue;
        std::array<ir::ValueId, 3> means{ir::kNoValue, ir::kNoValue, ir::kNoValue};
        std::optional<LatticeShape> screen;
    };
    std::optional<Runs> runs;
};

struct LayerFields {
    ir::ValueId index;    // fractional member index: member n is {index = n}
    ir::ValueId distance; // world distance to the nearest member
    ir::ValueId gradX = ir::kNoValue, gradY = ir::kNoValue; // the index gradient, per world unit
    // Family-specific diagnostics (the walking solver's certified interval), for tests.
    ir::ValueId aux0 = ir::kNoValue, aux1 = ir::kNoValue;
    PhaseSample sample; // for the sweeping views; empty where the family gives none
    // A lattice's index is a pair (spec §3.6): the point's continuous coordinates (u, v) in
    // the lattice's basis, before rounding, are its two generators' index fields, with their
    // gradients per world unit. `index` and `aux0` stay the nearest point's integer pair and
    // `gradX` unset, so whatever reads a one-index family's fields sees a lattice as before.
    // kNoValue on every other family.
    ir::ValueId genU = ir::kNoValue, genUX = ir::kNoValue, genUY = ir::kNoValue;
    ir::ValueId genV = ir::kNoValue, genVX = ir::kNoValue, genVY = ir::kNoValue;
    // A lattice's next nearest point's world distance (where it draws its points, the nearest
    // point's runner-up, which is as near where the two tie). kNoValue on every other family.
    ir::ValueId runnerUp = ir::kNoValue;
    // Where `index` is a member's number rather than the fractional index (the pencil's
    // sector), the fractional index itself, whose gradient gradX, gradY are: what the
    // characters and the overlay read (Characters.h). kNoValue elsewhere (`index` is it).
    ir::ValueId smooth = ir::kNoValue;
    Footprint footprint; // for the mean filter; unset where the family is not a phase family
    CrowdEstimate crowd; // for the mean filter; unset but where a family estimates its crowd
};

// The stroke in world units: half-width h = max(t/2, 1.15 px) and antialias band
// a = 0.7 px, where px is the world size of a pixel (Eq. 35). Written once as a template
// (instantiated over IR values here, over double by the benchmarks that check the kernel).
constexpr double kStrokeFloorPixels = 1.15; // the thinnest half-width drawn, in pixels
constexpr double kAntialiasPixels = 0.7;    // the antialias band's half-width, in pixels
template <class T>
struct StrokeBandT {
    T h, a;
};
template <class T>
inline StrokeBandT<T> strokeBandOf(T stroke, T pixel, bool floored = true) {
    using std::max;
    T half = stroke * 0.5;
    T floor = pixel * (floored ? kStrokeFloorPixels : 0.0);
    T h = max(half, floor);
    T a = pixel * kAntialiasPixels;
    return {h, a};
}
struct StrokeBand {
    ir::ValueId h, a;
};
// floored false: h = t/2 at every zoom (LowerOptions::strokeFloor, for §8.2's experiment).
StrokeBand strokeBand(ir::Builder& b, ir::ValueId stroke, ir::ValueId pixel, bool floored = true);

// A phase family's fractional member index, (phi - phase) / spacing, the spacing held above
// 1e-6.
ir::ValueId indexOfPhase(ir::Builder& b, ir::ValueId phi, ir::ValueId phase, ir::ValueId spacing);

// Members are the level sets {phi = n s + phase}. The index is (phi - phase) / s; the nearest
// member is the rounded index (clamped to `first` when the family starts there), and the
// distance is the index residual over the index gradient's length (Eq. 5); short of the
// first member, where the excluded members' phase may be singular, Eq. 5 is applied to
// phi^2 instead (see the .cpp).
// `phiNear`, for a family with `first`, is the phase at a point a hair off this one (see the
// .cpp): on the fold itself (phi exactly 0) AD's gradient says nothing, and the one the
// distance needs there is read from that point.
LayerFields phaseFamilyFields(ir::Builder& b, ir::ValueId phi, ir::ValueId phase,
                              ir::ValueId spacing, std::optional<int> first,
                              ir::ValueId phiNear = ir::kNoValue);

// The phase sample (Eq. 14) of a phase family from its index, nearest member (clamped to
// `first`), |grad index|, and for a family with `first` its fold (the index is filled in).
PhaseSample phaseSample(ir::Builder& b, ir::ValueId index, ir::ValueId nearest, ir::ValueId grad,
                        const std::optional<FoldSample>& fold);

// Coverage of the stroke at distance `d` (Eq. 4):
// (1 - smoothstep(h - a, h + a, d)) * opacity * alpha, clamped to [0, 1], NaN read as 0.
// It is strokeInk's ink laid with inkCoverage; the mean filter (Prefilter.h) replaces the ink
// between the two.
ir::ValueId strokeCoverage(ir::Builder& b, ir::ValueId d, const StrokeBand& band,
                           ir::ValueId opacity, ir::ValueId alpha);
// The point rule's ink at distance `d`: 1 - smoothstep(h - a, h + a, d).
ir::ValueId strokeInk(ir::Builder& b, ir::ValueId d, const StrokeBand& band);
// `ink` times opacity and alpha (each clamped to [0, 1]), clamped to [0, 1], NaN read as 0.
ir::ValueId inkCoverage(ir::Builder& b, ir::ValueId ink, ir::ValueId opacity, ir::ValueId alpha);

// Premultiplied RGBA accumulated from the background up.
struct Ink {
    ir::ValueId r, g, b, a;
};
Ink paper(ir::Builder& b, ir::ValueId r, ir::ValueId g, ir::ValueId bl, ir::ValueId a);
// Lays ink of colour (r, g, bl) with coverage `cov` over `acc` (the running mix of §3.4).
Ink inkOver(ir::Builder& b, const Ink& acc, ir::ValueId r, ir::ValueId g, ir::ValueId bl,
            ir::ValueId cov);
// acc + scale x d, a correction to the running mix in premultiplied form (the covariance of
// strokes that meet, the correlation of a fine union), held to ink that can be: alpha in
// [0, 1], each channel in [0, alpha].
Ink addCorrection(ir::Builder& b, const Ink& acc, const Ink& d, ir::ValueId scale);
// Straight (unpremultiplied) colour and alpha of the result.
Ink unpremultiply(ir::Builder& b, const Ink& acc);

} // namespace moire::lower
