#include "compiler/lower/Prefilter.h"

#include "compiler/ir/Semantics.h"
#include "compiler/lower/DistanceReading.h"
#include "compiler/lower/FoldMean.h"

#include <span>

namespace moire::lower {

using ir::ValueId;

namespace {

// Whether the derivatives of `v` are not to be taken: it is computed from a derivative
// (Op::DerivX, DerivY; the AD pass is first order), or in a loop (a walking solver's search,
// through which AD would carry tangents on every step: the solver gives its index gradient
// instead). An If's result is read as computed from everything in its regions.
bool fromDerivative(const ir::Function& f, ValueId v) {
    std::vector<const ir::Inst*> def(f.numValues(), nullptr);
    for (const ir::Block& block : f.blocks)
        for (const ir::Inst& inst : block.insts)
            for (ValueId r : inst.results) def[r] = &inst;
    std::vector<char> seen(f.numValues(), 0);
    std::vector<char> blockSeen(f.blocks.size(), 0);
    std::vector<ValueId> todo{v};
    std::vector<const ir::Inst*> insts;
    while (!todo.empty() || !insts.empty()) {
        if (!insts.empty()) {
            const ir::Inst* inst = insts.back();
            insts.pop_back();
            if (inst->op == ir::Op::DerivX || inst->op == ir::Op::DerivY ||
                inst->op == ir::Op::Loop)
                return true;
            for (ValueId a : inst->args) todo.push_back(a);
            for (ir::BlockId r : inst->regions)
                if (!blockSeen[r]) {
                    blockSeen[r] = 1;
                    for (const ir::Inst& inner : f.blocks[r].insts) insts.push_back(&inner);
                }
            continue;
        }
        ValueId x = todo.back();
        todo.pop_back();
        if (x == ir::kNoValue || seen[x]) continue;
        seen[x] = 1;
        if (def[x]) insts.push_back(def[x]);
    }
    return false;
}

} // namespace

PixelSides onPixelSides(ir::Builder& b, ValueId x, ValueId y, const PixelFootprint& pixel) {
    if (pixel.cosTurn == ir::kNoValue) return {x, y};
    return {b.add(b.mul(x, pixel.cosTurn), b.mul(y, pixel.sinTurn)),
            b.sub(b.mul(y, pixel.cosTurn), b.mul(x, pixel.sinTurn))};
}

MemberNormal memberNormal(ir::Builder& b, ValueId distance, ValueId gradX, ValueId gradY,
                          const PixelFootprint& pixel) {
    ValueId gx = gradX, gy = gradY;
    const bool ofDistance = !fromDerivative(b.function(), distance);
    if (ofDistance) {
        gx = b.emit(ir::Op::DerivX, {distance});
        gy = b.emit(ir::Op::DerivY, {distance});
    }
    if (gx == ir::kNoValue || gy == ir::kNoValue) return {};
    PixelSides g = onPixelSides(b, gx, gy, pixel);
    return {g.u, g.v, ofDistance};
}

NormalExtents extentsAcross(ir::Builder& b, ValueId u, ValueId v, ValueId side) {
    ValueId length = b.hypot(u, v);
    ValueId some = b.gt(length, b.constF(0.0)); // false on NaN too
    ValueId scale = b.div(side, b.max(length, b.constF(1e-30)));
    return {b.select(some, b.mul(b.abs(u), scale), side),
            b.select(some, b.mul(b.abs(v), scale), b.constF(0.0))};
}

ValueId distanceInk(ir::Builder& b, ValueId distance, ValueId halfWidth, ValueId gradX,
                    ValueId gradY, const PixelFootprint& pixel) {
    // The nearest member's normal (memberNormal): its components along the pixel's sides,
    // times the pixel over its length, are the footprint's extents along the normal. Where
    // there is no normal, or it vanishes, the footprint is a box of the pixel's side.
    ValueId along = pixel.size, across = b.constF(0.0);
    MemberNormal n = memberNormal(b, distance, gradX, gradY, pixel);
    if (n.u != ir::kNoValue) {
        NormalExtents e = extentsAcross(b, n.u, n.v, pixel.size);
        along = e.along, across = e.across;
    }
    return distanceMeanInk(ir::BuiltValue(b, distance), ir::BuiltValue(b, halfWidth),
                           ir::BuiltValue(b, along), ir::BuiltValue(b, across))
        .id;
}

namespace {

// The closed form over a square of side `side` (world units) along the pixel's sides, the index
// and its gradient (per world unit; `grad` its length) read at its centre; with the index's
// steps across the square's two sides.
// The mean of part(ox, oy) over the pixel's n x n parts, (ox, oy) the world offset of a part's
// centre from the pixel's.
template <class Part>
ValueId meanOverParts(ir::Builder& b, const PixelFootprint& pixel, ValueId n, Part part) {
    const ValueId zero = b.constF(0.0);
    // Part k, in rows of n.
    std::vector<ValueId> out = b.loop(
        {zero, zero},
        [&](std::span<const ValueId> v) { return std::vector<ValueId>{b.lt(v[0], b.mul(n, n))}; },
        [&](std::span<const ValueId> v) {
            const ValueId row = b.floor(b.div(v[0], n));
            const ValueId col = b.sub(v[0], b.mul(row, n));
            const Offset o = offsetOf(b, place(b, col, n), place(b, row, n), pixel);
            return std::vector<ValueId>{b.add(v[0], b.constF(1.0)), b.add(v[1], part(o.ox, o.oy))};
        });
    return b.div(out[1], b.mul(n, n));
}

struct SquareMean {
    ValueId mean, along, across;
};
SquareMean squareMean(ir::Builder& b, ValueId index, ValueId gradX, ValueId gradY, ValueId grad,
                      ValueId halfWidth, ValueId side, const PixelFootprint& pixel) {
    // The index's steps across the square's two sides: the gradient's components along them.
    PixelSides g = onPixelSides(b, gradX, gradY, pixel);
    ValueId along = b.mul(b.abs(g.u), side), across = b.mul(b.abs(g.v), side);
    ValueId w = b.mul(halfWidth, grad); // half-width in index units
    const ValueId mean = squareMeanInk(ir::BuiltValue(b, index), ir::BuiltValue(b, along),
                                       ir::BuiltValue(b, across), ir::BuiltValue(b, w))
                             .id;
    return {mean, along, across};
}

} // namespace

ValueId meanInk(ir::Builder& b, const Footprint& footprint, ValueId distance, ValueId halfWidth,
                const PixelFootprint& pixel) {
    const SquareMean square = squareMean(b, footprint.index, footprint.gradX, footprint.gradY,
                                         footprint.grad, halfWidth, pixel.size, pixel);
    ValueId mean = square.mean;
    if (footprint.bent != ir::kNoValue) mean = b.mix(mean, footprint.bentMean, footprint.bent);
    if (!footprint.first && footprint.edge == ir::kNoValue) return mean;
    ValueId below = b.constB(false);
    if (footprint.first) {
        // Where the footprint reaches below the first member, the nearest member's distance
        // mean, or the parts' (belowFirstMean).
        below = reachesBelowFirst(b, footprint, pixel);
    }
    if (footprint.edge != ir::kNoValue) {
        // Where it reaches the region the members do not enter (within half the pixel's
        // diagonal and the stroke), the same.
        ValueId reach = b.add(b.mul(pixel.size, b.constF(kHalfDiagonal)), halfWidth);
        below = b.emit(ir::Op::Or, {below, b.lt(footprint.edge, reach)});
    }
    return b.ifThenElse(
        below,
        [&] {
            if (footprint.belowMean != ir::kNoValue)
                return std::vector<ValueId>{footprint.belowMean};
            return std::vector<ValueId>{
                distanceInk(b, distance, halfWidth, footprint.gradX, footprint.gradY, pixel)};
        },
        [&] { return std::vector<ValueId>{mean}; })[0];
}

ValueId reachesBelowFirst(ir::Builder& b, const Footprint& footprint, const PixelFootprint& pixel) {
    // Half the square's diagonal extent along the index: half its steps across the two sides.
    PixelSides g = onPixelSides(b, footprint.gradX, footprint.gradY, pixel);
    ValueId reach = b.mul(b.mul(b.add(b.abs(g.u), b.abs(g.v)), pixel.size), b.constF(0.5));
    return b.lt(b.sub(footprint.index, reach), b.constF(*footprint.first - 0.5));
}

namespace {

// grad P at a part (FoldAt): P's read off the fold, less 2 phi grad level.
PixelSides foldSlope(ir::Builder& b, const FoldAt& f, const PixelFootprint& pixel,
                     ValueId* length) {
    const ValueId twoPhi = b.mul(b.constF(2.0), b.sqrt(f.p));
    auto slope = [&](ir::Op d) {
        return b.sub(b.emit(d, {f.pNear}), b.mul(twoPhi, b.emit(d, {f.level})));
    };
    const ValueId gx = slope(ir::Op::DerivX), gy = slope(ir::Op::DerivY);
    *length = b.hypot(gx, gy);
    return onPixelSides(b, gx, gy, pixel);
}

} // namespace

ValueId belowFirstMean(ir::Builder& b, const FoldsAt& at, ValueId halfWidth,
                       const PixelFootprint& pixel, ValueId n) {
    const ValueId zero = b.constF(0.0);
    const PixelFootprint part{b.div(pixel.size, n), pixel.cosTurn, pixel.sinTurn};
    return meanOverParts(b, pixel, n, [&](ValueId ox, ValueId oy) {
        const FoldAt f = at(b, ox, oy);
        ValueId length;
        const PixelSides g = foldSlope(b, f, pixel, &length);
        auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
        const ValueId mean =
            foldMeanInk(value(f.p), value(b.mul(g.u, part.size)), value(b.mul(g.v, part.size)),
                        value(b.mul(halfWidth, length)), value(f.lead))
                .id;
        return b.denan(mean, zero);
    });
}

namespace {

// The departure, in pixels across the members, from which the pixel is read in parts, and past
// which by them alone. A circle of radius R pixels departs from its tangent by 1 / 4R at a
// corner, and the closed form's error on an edge bending so is about 1 / 24R of the pixel:
// 0.002 at 0.01 (R = 25).
constexpr double kBentFrom = 0.005, kBentFull = 0.015;
// The parts a side: 2, 4 or 8, the fewest that bring a bend's departure under kBentFrom in each
// (it shrinks with the square of a part's side: 2 parts a side below 4 kBentFrom, 4 below 16
// kBentFrom), and 8 where it folds. A wave's gentle bend engaged nearly every pixel of
// wave_over_lines: read in 8 x 8 parts everywhere it cost 7 times its frame, to mend 0.0001.
constexpr double kTwoParts = 4.0 * kBentFrom, kFourParts = 16.0 * kBentFrom;
constexpr int kMostParts = 8;
// P's departure from which the pixel is read in more parts (foldParts): a sixteenth of the
// index's. P's closed form takes its members' cells across each part at four midpoints, and
// where the parts are few about a hyperbola's centre, with the index's thresholds, windows
// there read 0.0007 to 0.0039 RMSE off the exact field; with these, 0.0002 to 0.0010, at the
// cost the index's parts had (docs/filtering.md, "Members crowding into a fold").
constexpr double kFoldBentFrom = kBentFrom / 16.0;

// The closed form over one part, `size` its side: its index and gradient read there (the
// gradient's length held above kTiny, as phaseFamilyFields holds the pixel's).
ValueId partMean(ir::Builder& b, ValueId index, ValueId halfWidth, ValueId size,
                 const PixelFootprint& pixel) {
    const ValueId gx = b.emit(ir::Op::DerivX, {index}), gy = b.emit(ir::Op::DerivY, {index});
    const ValueId grad = b.max(b.hypot(gx, gy), b.constF(ir::kTiny));
    return b.denan(squareMean(b, index, gx, gy, grad, halfWidth, size, pixel).mean, b.constF(0.0));
}

} // namespace

Bend bendOf(ir::Builder& b, const IndexAt& at, const Footprint& footprint,
            const PixelFootprint& pixel) {
    const ValueId zero = b.constF(0.0);
    // The index at the corners against its linear model, each departure taken to the nearest
    // whole number (a phase's cut by whole members, the spiral's, departs by none).
    const PixelSides g = onPixelSides(b, footprint.gradX, footprint.gradY, pixel);
    ValueId most = zero;
    for (double a : {-0.5, 0.5})
        for (double c : {-0.5, 0.5}) {
            const Offset o = offsetOf(b, b.constF(a), b.constF(c), pixel);
            const ValueId linear =
                b.add(footprint.index,
                      b.mul(pixel.size, b.add(b.mul(g.u, b.constF(a)), b.mul(g.v, b.constF(c)))));
            const ValueId off = b.sub(at(b, o.ox, o.oy), linear);
            most = b.max(most, b.denan(b.abs(b.sub(off, b.round(off))), zero));
        }
    const ValueId acrossMembers = b.div(most, b.mul(footprint.grad, pixel.size));
    const ValueId weight =
        b.smoothstep(b.constF(kBentFrom), b.constF(kBentFull), b.denan(acrossMembers, zero));
    const ValueId n = b.select(b.lt(acrossMembers, b.constF(kTwoParts)), b.constF(2.0),
                               b.select(b.lt(acrossMembers, b.constF(kFourParts)), b.constF(4.0),
                                        b.constF(double(kMostParts))));
    return {weight, n};
}

ValueId foldParts(ir::Builder& b, const FoldsAt& at, const IndexAt& indexAt,
                  const PixelFootprint& pixel, ValueId least) {
    const ValueId zero = b.constF(0.0);
    const FoldAt f = at(b, zero, zero);
    ValueId length;
    const PixelSides g = foldSlope(b, f, pixel, &length);
    // P at the corners and the sides' middles against its linear model folded at 0 (its far
    // side's P counts back): a saddle such as x^2 - y^2 departs from its tangent plane along
    // the pixel's sides and not at all along its diagonals.
    ValueId most = zero;
    for (double a : {-0.5, 0.0, 0.5})
        for (double c : {-0.5, 0.0, 0.5}) {
            if (a == 0.0 && c == 0.0) continue;
            const Offset o = offsetOf(b, b.constF(a), b.constF(c), pixel);
            const ValueId linear = b.abs(b.add(
                f.p, b.mul(pixel.size, b.add(b.mul(g.u, b.constF(a)), b.mul(g.v, b.constF(c))))));
            const ValueId phi = b.add(indexAt(b, o.ox, o.oy), f.level);
            most = b.max(most, b.abs(b.sub(b.mul(phi, phi), linear)));
        }
    // In pixels across P's steps; NaN (no gradient) reads as bent throughout.
    const ValueId across = b.denan(b.div(most, b.mul(length, pixel.size)), b.constF(1.0));
    const ValueId n = b.select(b.lt(across, b.constF(kFoldBentFrom)), b.constF(1.0),
                               b.select(b.lt(across, b.constF(4.0 * kFoldBentFrom)), b.constF(2.0),
                                        b.select(b.lt(across, b.constF(16.0 * kFoldBentFrom)),
                                                 b.constF(4.0), b.constF(double(kMostParts)))));
    return b.max(n, least);
}

BentIndex bentIndexMean(ir::Builder& b, const IndexAt& at, const Footprint& footprint,
                        ValueId halfWidth, const PixelFootprint& pixel) {
    const ValueId zero = b.constF(0.0);
    const auto [weight, n] = bendOf(b, at, footprint, pixel);
    const ValueId mean = b.ifThenElse(
        b.gt(weight, zero),
        [&] {
            const ValueId side = b.div(pixel.size, n);
            return std::vector<ValueId>{meanOverParts(b, pixel, n, [&](ValueId ox, ValueId oy) {
                return partMean(b, at(b, ox, oy), halfWidth, side, pixel);
            })};
        },
        [&] { return std::vector<ValueId>{zero}; })[0];
    return {weight, mean};
}

ValueId crowdInk(ir::Builder& b, const CrowdEstimate& crowd, ValueId ink) {
    // The members beside the nearest, where the family resolved them: the mean of their union
    // with the nearest's stroke, less the nearest's own (WalkingFamily.cpp), added to the
    // nearest's mean as drawn across its normal, up to a pixel full.
    if (crowd.others != ir::kNoValue) ink = b.min(b.add(ink, crowd.others), b.constF(1.0));
    // Weighted by `engaged` alone, not handed over by members per pixel as a phase family's
    // mean is: the hand-over keeps resolved members drawn as strokes, but where a family
    // cannot resolve its members itself (a strided scan) the strokes it draws are a subset of
    // them, whatever their size on screen, and their ink is short by the members skipped.
    return b.mix(ink, crowd.mean, crowd.engaged);
}

ValueId layerMeanInk(ir::Builder& b, const LayerFields& fields, ValueId halfWidth,
                     const PixelFootprint& pixel) {
    ValueId ink =
        fields.footprint.grad != ir::kNoValue
            ? meanInk(b, fields.footprint, fields.distance, halfWidth, pixel)
        : fields.crowd.nearest != ir::kNoValue
            ? fields.crowd.nearest
            : distanceInk(b, fields.distance, halfWidth, fields.gradX, fields.gradY, pixel);
    if (fields.crowd.mean != ir::kNoValue) ink = crowdInk(b, fields.crowd, ink);
    return ink;
}

} // namespace moire::lower
