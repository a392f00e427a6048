#include "compiler/lower/StrokePairs.h"

#include "compiler/lower/FineUnion.h"
#include "compiler/lower/LatticeUnion.h"

#include <span>
#include <vector>

namespace moire::lower {

using ir::ValueId;

namespace {
// A pitch (pixels) that puts a layer's next members past any pixel's reach: where it has no
// next members near (below a first member) or none to speak of (no gradient).
constexpr double kFarPitch = 1e6;
} // namespace

std::optional<StrokeAcross> strokeAcross(ir::Builder& b, const LayerFields& fields,
                                         ValueId halfWidth, const PixelFootprint& pixel) {
    ValueId zero = b.constF(0.0), one = b.constF(1.0);
    ValueId nu, nv, s, weight = one;
    StrokeAcross out; // its periodic reading, where a phase family has one, and a dot's disc
    // The members' pitch in pixels from how many a pixel crosses, held finite where none does.
    auto pitchOf = [&](ValueId members) {
        return b.div(one, b.max(members, b.constF(1.0 / kFarPitch)));
    };
    if (fields.footprint.grad != ir::kNoValue && fields.footprint.gradX != ir::kNoValue &&
        fields.footprint.edge == ir::kNoValue) {
        // A phase family: members at the integers of the index, which grows along its
        // gradient g by |g| a world unit, so the pixel's centre stands residual / |g| past
        // the nearest member along g.
        const Footprint& f = fields.footprint;
        PixelSides g = onPixelSides(b, f.gradX, f.gradY, pixel);
        ValueId length = b.max(b.hypot(g.u, g.v), b.constF(1e-30));
        nu = b.div(g.u, length);
        nv = b.div(g.v, length);
        ValueId residual = b.sub(f.index, b.floor(b.add(f.index, b.constF(0.5))));
        s = b.div(residual, b.mul(length, pixel.size));
        // Members closer than a few pixels: the nearest alone is not the pixel's ink (and a
        // run of such layers is FineUnion's to correlate).
        ValueId members = b.mul(length, pixel.size);
        weight = b.sub(one, b.smoothstep(b.constF(kCrowdFrom), b.constF(kCrowdFull), members));
        out.pitch = pitchOf(members);
        out.index = f.index;
        out.gu = b.mul(g.u, pixel.size);
        out.gv = b.mul(g.v, pixel.size);
        out.w = b.mul(halfWidth, f.grad);
        out.unresolved = unresolved(b, f, pixel);
        if (f.first) {
            // Where the footprint reaches below the first member (meanInk's test), that member
            // is the nearest, on the gradient's far side, `distance` away (the index is not
            // linear there: it folds), and it alone is the pixel's ink.
            ValueId below = reachesBelowFirst(b, f, pixel);
            s = b.select(below, b.sub(zero, b.div(fields.distance, pixel.size)), s);
            weight = b.select(below, one, weight);
            out.pitch = b.select(below, b.constF(kFarPitch), out.pitch);
        }
    } else {
        MemberNormal n = memberNormal(b, fields.distance, fields.gradX, fields.gradY, pixel);
        if (n.u == ir::kNoValue) return std::nullopt;
        ValueId length = b.hypot(n.u, n.v);
        ValueId some = b.gt(length, zero); // false on NaN too
        ValueId safe = b.max(length, b.constF(1e-30));
        nu = b.div(n.u, safe);
        nv = b.div(n.v, safe);
        s = b.div(fields.distance, pixel.size);
        if (!n.ofDistance) {
            // The normal is the index gradient (the walking solver's): the pixel stands on
            // the side of the nearest member its index residual says, the fractional index
            // growing along the gradient (LayerFields::smooth where `index` is a member's
            // number).
            ValueId index = fields.smooth != ir::kNoValue ? fields.smooth : fields.index;
            ValueId residual = b.sub(index, b.floor(b.add(index, b.constF(0.5))));
            s = b.select(b.lt(residual, zero), b.sub(zero, s), s);
        }
        weight = b.select(some, one, zero);
        if (fields.footprint.grad != ir::kNoValue) {
            // A family averaged by its index but read here by its distance (Footprint::edge):
            // where its members crowd, the nearest alone is not the pixel's ink either.
            ValueId members = b.mul(fields.footprint.grad, pixel.size);
            weight = b.mul(weight, b.sub(one, b.smoothstep(b.constF(kCrowdFrom),
                                                           b.constF(kCrowdFull), members)));
            // Its members stand 1 / |grad index| apart along the normal (the pencil's rays,
            // locally parallel), but within a couple of pixels of the region they do not
            // enter (Footprint::edge) the nearest stroke may be that region's rim.
            if (const ValueId edge = fields.footprint.edge; edge != ir::kNoValue)
                out.pitch = b.select(b.lt(edge, b.mul(pixel.size, b.constF(2.0))),
                                     b.constF(kFarPitch), pitchOf(members));
        }
    }
    if (const auto& runs = fields.crowd.runs;
        runs && out.unresolved == ir::kNoValue && runs->footprint.gradX != ir::kNoValue) {
        // A family given by its distance whose members crowd running one way: periodic
        // strokes by the index they run by (not where they run two or three ways, a grid's).
        const Footprint& f = runs->footprint;
        PixelSides g = onPixelSides(b, f.gradX, f.gradY, pixel);
        out.index = f.index;
        out.gu = b.mul(g.u, pixel.size);
        out.gv = b.mul(g.v, pixel.size);
        out.w = b.mul(runs->halfWidth, f.grad);
        out.unresolved = b.select(b.gt(runs->twoWays, zero), zero, unresolved(b, f, pixel));
    }
    const ValueId crowded = fields.crowd.strokesCrowded != ir::kNoValue
                                ? fields.crowd.strokesCrowded
                                : fields.crowd.engaged;
    if (crowded != ir::kNoValue) weight = b.mul(weight, b.sub(one, b.clamp(crowded, zero, one)));
    // A lattice's dots in rows a pixel apart or closer: each dot over the pixel is still
    // counted exactly (LatticeCrowd.cpp), but the nearest is not the pixel's ink, and two such
    // screens are correlated as screens (LatticeUnion.h).
    if (const auto& p = fields.crowd.shape) {
        ValueId alone = b.sub(one, dotsCrowded(b, *p, pixel));
        if (fields.runnerUp != ir::kNoValue) {
            // The nearest dot's stroke turns with the dot: where two stand equally near the
            // pixel's centre it flips from one to the other, and double and float may pick
            // different ones. Weighed to 0 at the tie, over kTieBand pixels of the runner-up's
            // lead, the pair's term is continuous across it.
            ValueId lead = b.div(b.sub(fields.runnerUp, fields.distance),
                                 b.mul(pixel.size, b.constF(kTieBand)));
            alone = b.mul(alone, b.clamp(lead, zero, one));
        }
        weight = b.mul(weight, b.select(p->dots, alone, one));
        out.disc = b.select(p->dots, one, zero);
    }
    out.nu = nu;
    out.nv = nv;
    out.s = s;
    out.h = b.div(halfWidth, pixel.size);
    out.weight = weight;
    out.touches = b.emit(
        ir::Op::And, {b.gt(weight, zero), b.lt(b.abs(s), b.add(out.h, b.constF(kHalfDiagonal)))});
    return out;
}

ValueId strokeCovariance(ir::Builder& b, const StrokeAcross& first, const StrokeAcross& second) {
    // The second stroke's normal in the first's frame: cos and sin of the angle between them.
    ValueId cosA = b.add(b.mul(first.nu, second.nu), b.mul(first.nv, second.nv));
    ValueId sinA = b.sub(b.mul(first.nu, second.nv), b.mul(first.nv, second.nu));
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    auto pair = [&](ValueId s1, ValueId h1, ValueId s2, ValueId h2) {
        return stripCovariance(value(s1), value(h1), value(s2), value(h2), value(cosA), value(sinA))
            .id;
    };
    auto runs = [](const StrokeAcross& s) { return s.pitch != ir::kNoValue; };
    ValueId cov;
    if (!runs(first) && !runs(second)) {
        cov = pair(first.s, first.h, second.s, second.h);
    } else {
        // Each member's stroke cut to half its pitch: members that overlap tile their band.
        auto cut = [&](const StrokeAcross& s) {
            return runs(s) ? b.min(s.h, b.mul(s.pitch, b.constF(0.5))) : s.h;
        };
        const ValueId h1 = cut(first), h2 = cut(second);
        // The members whose strokes reach the pixel, `lo` to lo + count - 1 about the nearest
        // (-1, 0, 1): the nearest always does where the pair is read, its neighbours only where
        // the members stand about two pixels apart or closer. A layer without a pitch, its
        // nearest alone.
        const ValueId zero = b.constF(0.0), one = b.constF(1.0);
        struct Members {
            ValueId lo, count;
        };
        auto members = [&](const StrokeAcross& s, ValueId h) {
            if (!runs(s)) return Members{zero, one};
            const ValueId reach = b.add(h, b.constF(kHalfDiagonal));
            auto reaches = [&](ValueId offset) { return b.lt(b.abs(offset), reach); };
            const ValueId lo = b.select(reaches(b.sub(s.s, s.pitch)), b.constF(-1.0), zero);
            const ValueId hi = b.select(reaches(b.add(s.s, s.pitch)), one, zero);
            return Members{lo, b.add(b.sub(hi, lo), one)};
        };
        const Members m1 = members(first, h1), m2 = members(second, h2);
        // Pair k of the m1 x m2 that reach: one loop, the pair's IR written once.
        const std::vector<ValueId> sums = b.loop(
            {zero, zero},
            [&](std::span<const ValueId> v) {
                return std::vector<ValueId>{b.lt(v[0], b.mul(m1.count, m2.count))};
            },
            [&](std::span<const ValueId> v) {
                const ValueId row = b.floor(b.div(b.add(v[0], b.constF(0.5)), m2.count));
                const ValueId column = b.sub(v[0], b.mul(row, m2.count));
                auto member = [&](const StrokeAcross& s, const Members& m, ValueId k) {
                    return runs(s) ? b.add(s.s, b.mul(b.add(m.lo, k), s.pitch)) : s.s;
                };
                const ValueId term =
                    pair(member(first, m1, row), h1, member(second, m2, column), h2);
                return std::vector<ValueId>{b.add(v[0], one), b.add(v[1], term)};
            });
        cov = sums[1];
    }
    return b.denan(b.mul(cov, b.mul(first.weight, second.weight)), b.constF(0.0));
}

ValueId stripesCovarianceOf(ir::Builder& b, ValueId index, ValueId gu, ValueId gv, ValueId w,
                            ValueId nu, ValueId nv, ValueId s, ValueId h, ValueId disc) {
    auto value = [&](ValueId v) { return ir::BuiltValue(b, v); };
    const ValueId zero = b.constF(0.0);
    const std::vector<ValueId> sums = b.loop(
        {zero, zero, zero},
        [&](std::span<const ValueId> v) {
            return std::vector<ValueId>{b.lt(v[0], b.constF(kStripeSlices))};
        },
        [&](std::span<const ValueId> v) {
            const auto [box, ink] =
                stripeSlice(value(index), value(gu), value(gv), value(w), value(nu), value(nv),
                            value(s), value(h), value(disc), value(v[0]));
            return std::vector<ValueId>{b.add(v[0], b.constF(1.0)), b.add(v[1], ink.id),
                                        b.add(v[2], box.id)};
        });
    const ValueId whole =
        squareMeanInk(value(index), value(b.abs(gu)), value(b.abs(gv)), value(w)).id;
    return b.sub(sums[1], b.mul(sums[2], whole));
}

ValueId mixedWeight(ir::Builder& b, const StrokeAcross& periodic, const StrokeAcross& stroke) {
    if (periodic.unresolved == ir::kNoValue) return b.constF(0.0);
    // The stroke's layer is resolved as far as its nearest stroke counts (its weight).
    return b.clamp(b.sub(periodic.unresolved, b.sub(b.constF(1.0), stroke.weight)), b.constF(0.0),
                   b.constF(1.0));
}

ValueId mixedCovariance(ir::Builder& b, const StrokeAcross& periodic, const StrokeAcross& stroke) {
    if (periodic.unresolved == ir::kNoValue) return b.constF(0.0);
    ValueId cov = stripesCovarianceOf(b, periodic.index, periodic.gu, periodic.gv, periodic.w,
                                      stroke.nu, stroke.nv, stroke.s, stroke.h,
                                      stroke.disc == ir::kNoValue ? b.constF(0.0) : stroke.disc);
    return b.denan(b.mul(cov, mixedWeight(b, periodic, stroke)), b.constF(0.0));
}

ValueId mixedPairCovariance(ir::Builder& b, const StrokeAcross& first, const StrokeAcross& second) {
    ValueId zero = b.constF(0.0);
    // Each way the term can run: `periodic` crowds past the hand-over beyond `stroke`, whose
    // stroke reaches the pixel.
    auto way = [&](const StrokeAcross& periodic, const StrokeAcross& stroke) {
        return b.emit(ir::Op::And, {stroke.touches, b.gt(mixedWeight(b, periodic, stroke), zero)});
    };
    auto oneWay = [&](const StrokeAcross& periodic, const StrokeAcross& stroke) {
        return b.ifThenElse(
            way(periodic, stroke),
            [&] { return std::vector<ValueId>{mixedCovariance(b, periodic, stroke)}; },
            [&] { return std::vector<ValueId>{zero}; })[0];
    };
    const bool firstRuns = first.unresolved != ir::kNoValue;
    const bool secondRuns = second.unresolved != ir::kNoValue;
    if (!firstRuns && !secondRuns) return zero;
    if (!secondRuns) return oneWay(first, second);
    if (!firstRuns) return oneWay(second, first);
    // Both layers can be read as periodic strokes. The two ways exclude each other wherever a
    // layer's weight and its unresolved share add to at most 1 (the hand-over's two sides):
    // u1 > 1 - w2 >= u2 and u2 > 1 - w1 >= u1 cannot both hold. So one stripes loop, its
    // operands picked by the way that runs, serves the pair (half the kernel's code for the
    // term); where both ways run after all, the larger weight's is taken.
    ValueId w12 = mixedWeight(b, first, second), w21 = mixedWeight(b, second, first);
    ValueId one2 = way(first, second), two1 = way(second, first);
    ValueId firstCrowds = b.emit(
        ir::Op::And,
        {one2, b.emit(ir::Op::Or, {b.emit(ir::Op::Not, {two1}), b.emit(ir::Op::Ge, {w12, w21})})});
    return b.ifThenElse(
        b.emit(ir::Op::Or, {one2, two1}),
        [&] {
            auto pick = [&](ValueId a, ValueId c) { return b.select(firstCrowds, a, c); };
            auto disc = [&](const StrokeAcross& s) {
                return s.disc == ir::kNoValue ? zero : s.disc;
            };
            // The periodic side's index and the stroke side's placement, each from the layer
            // that plays it.
            const StrokeAcross &a = first, &c = second;
            ValueId cov =
                stripesCovarianceOf(b, pick(a.index, c.index), pick(a.gu, c.gu), pick(a.gv, c.gv),
                                    pick(a.w, c.w), pick(c.nu, a.nu), pick(c.nv, a.nv),
                                    pick(c.s, a.s), pick(c.h, a.h), pick(disc(c), disc(a)));
            return std::vector<ValueId>{b.denan(b.mul(cov, pick(w12, w21)), zero)};
        },
        [&] { return std::vector<ValueId>{zero}; })[0];
}

std::vector<StrokeAcross> strandStrokes(ir::Builder& b, const CrowdEstimate& crowd,
                                        ValueId halfWidth, const PixelFootprint& pixel) {
    std::vector<StrokeAcross> out;
    if (crowd.strandsOn == ir::kNoValue) return out;
    for (const Footprint& f : crowd.strands) {
        LayerFields line;
        line.footprint = f;
        std::optional<StrokeAcross> s = strokeAcross(b, line, halfWidth, pixel);
        if (!s) continue;
        s->weight = b.select(crowd.strandsOn, s->weight, b.constF(0.0));
        if (s->unresolved != ir::kNoValue)
            s->unresolved = b.select(crowd.strandsOn, s->unresolved, b.constF(0.0));
        s->touches = b.emit(ir::Op::And, {s->touches, crowd.strandsOn});
        out.push_back(*s);
    }
    return out;
}

ValueId strandCrossings(ir::Builder& b, const std::vector<StrokeAcross>& strokes,
                        const std::vector<ValueId>& means) {
    ValueId zero = b.constF(0.0);
    if (strokes.size() != 3) return zero;
    ValueId covs = zero, least = b.constF(1.0), thinnest = b.constF(1.0);
    for (size_t i = 0; i < strokes.size(); ++i) {
        thinnest = b.min(thinnest, means[i]);
        for (size_t j = i + 1; j < strokes.size(); ++j) {
            // Behind a branch: most pixels meet one line or none.
            ValueId meet = b.emit(ir::Op::And, {strokes[i].touches, strokes[j].touches});
            // The nearest lines alone (no pitch): where the rows stand close enough for the
            // next lines to reach the pixel, the lattice reads its edges over the pixel whole
            // (TriangleInPixel.h, `engaged`), and with them this took a third longer and moved
            // no window of the tests.
            StrokeAcross one = strokes[i], other = strokes[j];
            one.pitch = other.pitch = ir::kNoValue;
            ValueId cov = b.ifThenElse(
                meet, [&] { return std::vector<ValueId>{strokeCovariance(b, one, other)}; },
                [&] { return std::vector<ValueId>{zero}; })[0];
            covs = b.add(covs, cov);
            least = b.min(least, b.add(cov, b.mul(means[i], means[j])));
        }
    }
    // E[x_1 x_2 x_3]: the least pair's E[x_i x_j], three quarters of it where the strokes are
    // thin against the pixel (the hexagon in the rhombus) rising to all of it where the pixel
    // lies within every stroke (the thinnest mean 1).
    ValueId triple =
        b.mul(b.max(least, zero), b.add(b.constF(0.75), b.mul(b.constF(0.25), thinnest)));
    ValueId resolved = b.min(b.min(strokes[0].weight, strokes[1].weight), strokes[2].weight);
    ValueId all = b.mul(b.mul(means[0], means[1]), means[2]);
    return b.denan(b.sub(b.mul(resolved, b.sub(triple, all)), covs), zero);
}

} // namespace moire::lower
