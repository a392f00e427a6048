// The walking solver's crowd over a few turns, drawn member by member where the scan strides
// (WalkingDensity.cpp hands over to it by the interval's turns): the crossings of h_p(n) = 0
// in n and the turns of h within reach of 0, each a window of members drawn over the pixel's
// cells.
#include "compiler/lower/Bisection.h"
#include "compiler/lower/WalkingSolver.h"

namespace moire::lower::walking {

// Why cells. Members of one window (consecutive members about a crossing or a turn of h)
// are nearly parallel at the pixel, sorted along their common normal, and their union is exact
// by inclusion and exclusion, each stroke less its overlap with the one before. Windows of
// different turns cross the pixel at the angles their turns make, from nearly parallel to
// square, and laid over one another as independent inks over the whole pixel they counted
// twice what two nearly parallel strokes share: circles turning a degree a member drew 0.95
// where the exact field has 0.86, its five strokes from five turns. Over a cell of a third of
// the pixel's side a stroke of a pixel or more inks all or nothing but at its edges, so laid
// independently cell by cell they share what they share (0.861 there; over the frame
// 1.6% of pixels off by more than 8/255 with 2 x 2 cells, 0.3% with 3 x 3).
Solver::CellFrame Solver::cellFrame(ValueId n) {
    ValueId psi = b_.mul(n, in_.turn);
    auto [nx, ny] = memberNormal(b_, pointAccess(), n, psi, b_.max(memberPixel(), c(1e-6)));
    auto [gx, gy] = toPixelFrame(nx, ny);
    PixelSides g = onPixelSides(b_, gx, gy, PixelFootprint{ir::kNoValue, in_.cosTurn, in_.sinTurn});
    ValueId length = b_.hypot(g.u, g.v);
    ValueId some = b_.gt(length, c(0.0)); // false on NaN too
    ValueId scale = b_.div(memberPixel(), b_.max(length, c(1e-30)));
    // The residual's change along each of the pixel's sides, over the pixel.
    ValueId du = b_.select(some, b_.mul(g.u, scale), c(0.0));
    ValueId dv = b_.select(some, b_.mul(g.v, scale), c(0.0));
    CellFrame f;
    f.side = b_.mul(memberPixel(), c(1.0 / kCellsPerSide));
    for (int i = 0; i < kCellsPerSide; ++i)
        for (int j = 0; j < kCellsPerSide; ++j) {
            const double ou = (i + 0.5) / kCellsPerSide - 0.5, ov = (j + 0.5) / kCellsPerSide - 0.5;
            f.shift[i * kCellsPerSide + j] = b_.add(b_.mul(du, c(ou)), b_.mul(dv, c(ov)));
        }
    return f;
}

// Stroke `h` added to each cell's union of a sorted run: the part of it the stroke before
// (`before`; kFar for none) leaves, one band of residuals (strokes of one width sorted along
// their normal: each adds what lies past the one before). A cell is read as a box of its side
// facing the normal, whose spread along the normal has the square cell's second moment (s^2 /
// 12 whatever the angle): the band's share of the box. A stroke past the pixel's reach adds
// nothing.
Vals Solver::addToCells(const CellFrame& f, std::span<const ValueId> unions, ValueId before,
                        ValueId h, ValueId reach) {
    ValueId half = memberHalf();
    return b_.ifThenElse(
        b_.lt(b_.abs(h), reach),
        [&] {
            ValueId up = b_.le(before, h);
            ValueId lo =
                b_.select(up, b_.max(b_.sub(h, half), b_.add(before, half)), b_.sub(h, half));
            ValueId hi =
                b_.select(up, b_.add(h, half), b_.min(b_.add(h, half), b_.sub(before, half)));
            ValueId edge = b_.mul(f.side, c(0.5));
            ValueId perSide = b_.div(c(1.0), f.side);
            Vals out(kCells);
            for (int k = 0; k < kCells; ++k) {
                ValueId top = b_.min(b_.add(hi, f.shift[k]), edge);
                ValueId bottom = b_.max(b_.add(lo, f.shift[k]), b_.neg(edge));
                ValueId covered = b_.max(b_.sub(top, bottom), c(0.0));
                out[k] = b_.add(unions[k], b_.mul(covered, perSide));
            }
            return out;
        },
        [&] { return Vals(unions.begin(), unions.end()); });
}

// A member's residual, or kFar before the first member (members start at n = 0).
ValueId Solver::memberResidual(ValueId n) {
    return b_.select(b_.lt(n, c(0.0)), c(kFar), residual(member(n)));
}

// One window of members drawn over the cells, about member `centre` (its normal's frame): the
// members from `left` down (none at or below `floor`, drawn already) and from `right` up,
// walked in the order of their residuals from the least (sigma = 1) or the greatest (-1),
// the nearer of the next on either side first, `steps` of them. A crossing's window walks one
// side (its left starts at `floor`): h is monotone across a crossing, so its members are a
// run sorted along their common normal. About a turn of h the members either side are each a
// run moving away from h there, interleaved along the normal, and walked in order they are
// one sorted run too. Where more than kCrossingRun of a crossing's members reach the pixel
// (`d` members per unit of residual there; 0 for none) it hands over, by five members, to
// its even comb, min(1, width d). Returns {last member drawn on the right, each cell's ink}.
Vals Solver::windowCells(ValueId centre, ValueId left, ValueId right, ValueId floor, ValueId steps,
                         ValueId sigma, ValueId d, ValueId width) {
    const CellFrame f = cellFrame(centre);
    const ValueId reach = strokeReach();
    ValueId far = b_.mul(sigma, c(kFar));
    auto leftOpen = [&](ValueId n) { return both(b_.gt(n, floor), b_.le(c(0.0), n)); };
    auto leftSide = [&](ValueId n) { return b_.select(leftOpen(n), residual(member(n)), far); };
    // Carried: the step, the next member either side and its residual, the last residual.
    Vals init{c(0.0), left, leftSide(left), right, memberResidual(right), c(kFar)};
    for (int k = 0; k < kCells; ++k) init.push_back(c(0.0));
    Vals walk = b_.loop(
        init, [&](std::span<const ValueId> v) { return Vals{b_.lt(v[0], steps)}; },
        [&](std::span<const ValueId> v) {
            ValueId takeLeft = b_.lt(b_.mul(sigma, v[2]), b_.mul(sigma, v[4]));
            ValueId h = b_.select(takeLeft, v[2], v[4]);
            ValueId nextLeft = b_.select(takeLeft, b_.sub(v[1], c(1.0)), v[1]);
            ValueId nextRight = b_.select(takeLeft, v[3], b_.add(v[3], c(1.0)));
            // One residual a step, the next member's on the side taken.
            ValueId hTaken = residual(member(b_.select(takeLeft, nextLeft, nextRight)));
            ValueId hNext = b_.select(takeLeft, b_.select(leftOpen(nextLeft), hTaken, far),
                                      b_.select(b_.lt(nextRight, c(0.0)), c(kFar), hTaken));
            Vals out{b_.add(v[0], c(1.0)),
                     nextLeft,
                     b_.select(takeLeft, hNext, v[2]),
                     nextRight,
                     b_.select(takeLeft, v[4], hNext),
                     h};
            Vals cells = addToCells(f, v.subspan(6), v[5], h, reach);
            out.insert(out.end(), cells.begin(), cells.end());
            return out;
        });
    ValueId comb = b_.min(c(1.0), b_.mul(width, d));
    // How many of the crossing's members reach the pixel.
    ValueId reaching = b_.mul(b_.mul(reach, c(2.0)), d);
    ValueId drawn =
        b_.sub(c(1.0), b_.smoothstep(c(kCrossingRun - 1.0), c(kCrossingRun + 1.0), reaching));
    Vals out{b_.sub(walk[3], c(1.0))};
    for (int k = 0; k < kCells; ++k)
        out.push_back(b_.mix(comb, b_.min(walk[6 + k], c(1.0)), drawn));
    return out;
}

// Few turns: where the members turn, h_p(n) is not convex in n (with no turn it is, and
// chains() draws it), but over a few turns it crosses zero a few times, twice a turn at most
// for the far members, and turns back between. Sampled at `samples` members evenly over
// [lo, hi]:
//  - each sign change between two samples is refined by bisection to the two members it falls
//    between, and the kCrossingRun members either side of it are drawn (windowCells);
//  - where a sample is further along than both its neighbours (h turns back between them),
//    the member m where h turns is found by bisection on the sign of h(n + 1) - h(n). Where h
//    turns on the other side of zero from the samples, with no sign change between them, it
//    dipped through zero and back unseen, and both crossings are found on either side of m
//    and drawn; where it turns on their side within reach of the pixel, the members about m
//    are drawn (windowCells). Where h turns, its members crowd: at a degree a member, 500
//    units from the walk's middle, nine members about such a turn ink a pixel solid where no
//    sample sees a sign change.
// Each member is drawn once: a window starts past the last member drawn. The windows are laid
// over one another independently, cell by cell. Returns {density, ink}: the density the
// crossings' 1 / |dh/dn| (a turn within reach adds none).
Vals Solver::turnsDrawn(ValueId lo, ValueId hi, ValueId width, ValueId samples) {
    ValueId step = b_.div(b_.sub(hi, lo), samples);
    const ValueId reach = strokeReach();
    ValueId h0 = residual(lo);
    // Carried: the sample, its member and residual, the two before them (member, residual),
    // the last member drawn, the density, and each cell's paper.
    Vals init{c(1.0), lo, h0, lo, h0, b_.sub(lo, c(1.0)), c(0.0)};
    for (int k = 0; k < kCells; ++k) init.push_back(c(1.0));
    Vals res = b_.loop(
        init,
        [&](std::span<const ValueId> v) {
            return Vals{both(b_.le(v[0], samples), b_.lt(v[1], hi))};
        },
        [&](std::span<const ValueId> v) {
            ValueId n = b_.min(hi, b_.floor(b_.add(lo, b_.mul(v[0], step))));
            n = b_.max(n, b_.add(v[1], c(1.0)));
            ValueId h = residual(n);
            ValueId cross = changesSign(v[2], h);
            // h turns at the sample before this one (v[1], v[2]), between v[3] and n: at a
            // least value (sigma = 1) or a greatest (-1).
            ValueId sigma = b_.select(b_.lt(v[2], v[4]), c(1.0), c(-1.0));
            ValueId turns = both(b_.lt(c(0.0), b_.mul(sigma, b_.sub(h, v[2]))), b_.gt(v[1], v[3]));
            // Where h turns well clear of zero it matters not: the parabola through the three
            // samples puts its turn at v[2] - (h - v[4])^2 / (8 (h - 2 v[2] + v[4])) (equal
            // steps taken), and it is looked for only where that, or v[2], is within reach
            // of zero with a second difference to spare, or past it (on a circle's far field
            // this skips all but a few of the two turns a turn; the slope's bisection costs
            // two residuals a step).
            ValueId bend = b_.add(b_.sub(h, b_.mul(v[2], c(2.0))), v[4]);
            ValueId rise = b_.sub(h, v[4]);
            ValueId vertex = b_.sub(
                v[2], b_.div(b_.mul(rise, rise), b_.mul(b_.max(b_.abs(bend), c(1e-30)), c(8.0))));
            vertex = b_.mul(sigma, b_.min(b_.mul(sigma, vertex), b_.mul(sigma, v[2])));
            ValueId spare = b_.add(reach, b_.abs(bend));
            turns = both(
                turns, b_.emit(Op::Or, {b_.lt(b_.abs(vertex), spare), changesSign(v[2], vertex)}));
            // {m, h(m)}, or {n, h} where h does not turn.
            Vals turn = b_.ifThenElse(
                turns,
                [&] {
                    // The first member from which h no longer falls (sigma 1) or rises
                    // (-1): every j here is past the interval's start, a member already.
                    ValueId m = firstWhere(b_, v[3], b_.sub(n, c(1.0)), [&](ValueId j) {
                        ValueId slope = b_.sub(residual(b_.add(j, c(1.0))), residual(j));
                        return b_.le(c(0.0), b_.mul(sigma, slope));
                    });
                    return Vals{m, residual(m)};
                },
                [&] {
                    return Vals{n, h};
                });
            ValueId seen = b_.emit(Op::Or, {cross, changesSign(v[4], v[2])});
            ValueId unseen =
                both(both(turns, changesSign(v[2], turn[1])), b_.emit(Op::Not, {seen}));
            ValueId within = both(both(turns, b_.emit(Op::Not, {changesSign(v[2], turn[1])})),
                                  both(b_.lt(b_.abs(turn[1]), reach), b_.gt(turn[0], v[5])));
            // The windows: the members about a turn within reach, then the crossing before
            // m where h dipped through zero unseen and the one after it, or this interval's
            // own. Each is one pass of a loop, so that the window's IR is built once.
            ValueId sideM = negative(turn[1]), sideN = negative(h);
            Vals loopInit{c(0.0), v[5], c(0.0)};
            loopInit.insert(loopInit.end(), v.begin() + 7, v.end());
            Vals drawn = b_.loop(
                loopInit, [&](std::span<const ValueId> u) { return Vals{b_.lt(u[0], c(3.0))}; },
                [&](std::span<const ValueId> u) {
                    ValueId last = u[1];
                    ValueId atTurn = b_.lt(u[0], c(0.5));
                    ValueId first = b_.lt(u[0], c(1.5));
                    // Where this pass's crossing lies, if it has one.
                    ValueId a = b_.select(
                        unseen, b_.select(first, b_.add(v[3], c(1.0)), b_.add(turn[0], c(1.0))),
                        b_.add(v[1], c(1.0)));
                    ValueId bEnd = b_.select(both(unseen, first), turn[0], n);
                    ValueId side = b_.select(both(unseen, first), sideM, sideN);
                    ValueId crossing =
                        b_.emit(Op::Or, {unseen, both(cross, b_.emit(Op::Not, {first}))});
                    // {active, centre, left, right, floor, steps, sigma, d}
                    Vals window = b_.ifThenElse(
                        atTurn,
                        [&] {
                            ValueId m = turn[0];
                            return Vals{b_.select(within, c(1.0), c(0.0)),
                                        m,
                                        m,
                                        b_.add(m, c(1.0)),
                                        last,
                                        c(2.0 * kApproachRun + 1.0),
                                        sigma,
                                        c(0.0)};
                        },
                        [&] {
                            return b_.ifThenElse(
                                crossing,
                                [&] {
                                    ValueId z = firstWhere(b_, a, bEnd, [&](ValueId j) {
                                        return eq(negative(residual(j)), side);
                                    });
                                    ValueId hz = residual(z), hBefore = residual(b_.sub(z, c(1.0)));
                                    ValueId d = perResidual(b_.sub(hz, hBefore));
                                    // h is monotone across the crossing: where neither member
                                    // beside it reaches the pixel, none further out does.
                                    ValueId near =
                                        b_.lt(b_.min(b_.abs(hz), b_.abs(hBefore)), reach);
                                    ValueId from =
                                        b_.max(b_.sub(z, c(kCrossingRun)), b_.add(last, c(1.0)));
                                    ValueId to = b_.add(z, c(kCrossingRun));
                                    return Vals{b_.select(near, c(1.0), c(0.0)),
                                                z,
                                                b_.sub(from, c(1.0)),
                                                from,
                                                b_.sub(from, c(1.0)),
                                                b_.max(b_.sub(to, from), c(0.0)),
                                                c(1.0),
                                                d};
                                },
                                [&] { return Vals{c(0.0), n, n, n, n, c(0.0), c(1.0), c(0.0)}; });
                        });
                    Vals state{last};
                    state.insert(state.end(), u.begin() + 3, u.end());
                    Vals next = b_.ifThenElse(
                        b_.gt(window[0], c(0.0)),
                        [&] {
                            Vals ink = windowCells(window[1], window[2], window[3], window[4],
                                                   window[5], window[6], window[7], width);
                            Vals out{b_.max(last, ink[0])};
                            for (int k = 0; k < kCells; ++k)
                                out.push_back(b_.mul(state[1 + k], b_.sub(c(1.0), ink[1 + k])));
                            return out;
                        },
                        [&] { return state; });
                    ValueId density = b_.select(atTurn, c(0.0), window[7]);
                    Vals out{b_.add(u[0], c(1.0)), next[0], b_.add(u[2], density)};
                    out.insert(out.end(), next.begin() + 1, next.end());
                    return out;
                });
            Vals out{b_.add(v[0], c(1.0)), n, h, v[1], v[2], drawn[1], b_.add(v[6], drawn[2])};
            out.insert(out.end(), drawn.begin() + 3, drawn.end());
            return out;
        });
    ValueId paper = c(0.0);
    for (int k = 0; k < kCells; ++k) paper = b_.add(paper, res[7 + k]);
    return Vals{res[6], b_.sub(c(1.0), b_.mul(paper, c(1.0 / kCells)))};
}

} // namespace moire::lower::walking
