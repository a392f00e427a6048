// The mean ink over a square of a family whose phase folds, read where its members crowd
// towards the fold (docs/filtering.md, "Members crowding into a fold").
//
// A family with a first member has a phase that is the square root of a smooth function,
// phi = sqrt|Q| (the hyperbola's, Q = x^2 - y^2: the point rule's own reading below the first
// member, LayerPipeline.cpp, takes it so). Beside the fold phi runs as the square root of the
// distance to it and its members crowd in without end, n^2 s^2 / |grad Q| from it, so that no
// part of a pixel small enough to take phi as linear holds a countable number of them. Q does
// not bend there: in P = (phi / s)^2, linear over a part wherever Q is, member n stands at
// P = phi_n^2 (phi_n = l + n in units of the spacing, l the members' level) and its stroke,
// |phi - phi_n| / |grad phi| <= h, inks P within about a = h |grad P| of it, the same width
// for every member (reachUp, reachDown: a less or more a^2 / 4 phi_n^2). The members' cells
// meet halfway between them in phi, at (phi_n +- 1/2)^2, and the first member's reaches down
// to the fold, P = 0, where the point rule measures it by P itself (c^2 - P <= a). So the ink met
// from the fold up to P is a closed form (foldRunningInk), however many members that is:
//
//   C(P) = sum over whole cells n < m of min(a, phi_n + 1/4) + min(a, phi_n - 1/4)
//          (the first member's lower half min(a, phi_first^2); the cells where that is
//          furthest off by their members' exact reach),
//        + the part of cell m below P within its member's reach,
//
// each sum of min(a, x0 + j) over j < count in closed form: the terms below a are an
// arithmetic run. On the fold's far side Q < 0 and P = |Q| folds back: with P signed, C(|P|)
// sign(P) is the running ink along the part, and its difference over the part's extent along
// its steeper side, its mean there; across the other side it is taken at kFoldSlices midpoints.
#pragma once

#include "compiler/ir/BuiltValue.h"

#include <cmath>
#include <vector>

namespace moire::lower {

// Midpoints across the part's shallower side: its extent there is at most its steeper side's,
// over which each slice is exact.
constexpr int kFoldSlices = 4;

// sum over j = 0 .. count - 1 of min(a, x0 + j) (count a whole number, held at least 0).
template <class T>
T runOfLeast(T x0, T count, T a) {
    using std::floor;
    using std::max;
    using std::min;
    const T zero = ir::literal(a, 0.0);
    const T n = max(count, zero);
    // The terms below a: j < a - x0, ceil(a - x0) of them at most.
    const T below = min(max(zero - floor(x0 - a), zero), n);
    return below * x0 + below * (below - 1.0) * 0.5 + (n - below) * a;
}

// How far member phi's stroke reaches up and down in P: the point rule inks |phi - phi_n| <=
// a / 2 phi (its gradient, |grad P| / 2 phi, read at the point), so its edges stand where
// 2 phi |phi - phi_n| = a, a / 2 + a / (1 + sqrt(1 +- 2a / phi_n^2)) either side of phi_n^2
// (written so, not as the difference of two squares, for float); a below while the strokes
// are thin against the members' spacing, and the lower reach unbounded past
// phi_n^2 = 2a, where the cell's edge bounds it.
template <class T>
T reachUp(T phi, T a) {
    using std::sqrt;
    return a * 0.5 + a / (sqrt(a * 2.0 / (phi * phi) + 1.0) + 1.0);
}
template <class T>
T reachDown(T phi, T a) {
    using std::max;
    using std::sqrt;
    return a * 0.5 + a / (sqrt(max(1.0 - a * 2.0 / (phi * phi), ir::literal(a, 0.0))) + 1.0);
}

// The whole cells summed by their members' exact reach (below) where a alone is furthest
// off: the first member's (its reach down is a itself, so its reach up's difference,
// -a^2 / 4 phi^2, is not cancelled), and kExactAboutA members from the one about phi = a - 1,
// where a stroke's reach down meets its cell's edge and its reach up does not. Elsewhere the
// two reaches' differences cancel to a^3 / phi^4 or less (a stroke clipped by its cell on both
// sides has none): against every member summed by its exact reach, C is off by at most a
// quarter of a percent of the cell it stands in.
constexpr int kExactAboutA = 4;

// The members as foldRunningInk reads them: a, the first member's phi, and the exact cells'
// differences from a (each added where its cell lies below P's), computed once for a part.
template <class T>
struct FoldMembers {
    T a, lead, from;          // from: the first of the cells about phi = a - 1
    T firstLess;              // the first member's whole cell, exact less by a
    std::vector<T> aboutLess; // cells from, from + 1, ... (kExactAboutA)
};
template <class T>
FoldMembers<T> foldMembers(T a, T lead) {
    using std::floor;
    using std::max;
    using std::min;
    auto exactLess = [&](T phi, bool first) {
        T d = min(phi + 0.25, reachUp(phi, a)) - min(a, phi + 0.25);
        if (!first) d = d + min(phi - 0.25, reachDown(phi, a)) - min(a, phi - 0.25);
        return d;
    };
    FoldMembers<T> m{
        a, lead, max(floor(a - lead) - 1.0, ir::literal(a, 1.0)), exactLess(lead, true), {}};
    for (int i = 0; i < kExactAboutA; ++i)
        m.aboutLess.push_back(exactLess(lead + m.from + double(i), false));
    return m;
}

// C(P): the ink in P met from the fold up to P >= 0, for members at phi_n = lead + j (j >= 0,
// lead > 0 the first member's phi in spacings), each inking within its reach of phi_n^2; the
// first member's reach down is a, the point rule's fold distance (c^2 - P) / |grad P|.
template <class T>
T foldRunningInk(T P, const FoldMembers<T>& m) {
    using std::floor;
    using std::max;
    using std::min;
    using std::sqrt;
    const T a = m.a, lead = m.lead;
    const T zero = ir::literal(a, 0.0);
    // The whole cells below P's: k of them, the member of P's cell at lead + k.
    const T k = max(floor(sqrt(max(P, zero)) - lead + 0.5), zero);
    const auto some = ir::lessThan(zero, k);
    T whole = runOfLeast(lead + 0.25, k, a) + runOfLeast(lead + 0.75, k - 1.0, a) +
              ir::select(some, min(a, lead * lead) + m.firstLess, zero);
    for (int i = 0; i < kExactAboutA; ++i)
        whole = whole + ir::select(ir::lessThan(m.from + double(i), k), m.aboutLess[i], zero);
    const T member = lead + k;
    const T centre = member * member;
    const T cellFrom = ir::select(some, (member - 0.5) * (member - 0.5), zero);
    const T down = ir::select(some, reachDown(member, a), a);
    return whole + max(min(P, centre + reachUp(member, a)) - max(cellFrom, centre - down), zero);
}

// The mean of the folded members' ink over a square whose P runs from `centre` by `along` and
// `across` across its two sides (signed steps; P < 0 is the fold's far side), a = h |grad P|.
template <class T>
T foldMeanInk(T centre, T along, T across, T a, T lead) {
    using std::abs;
    using std::max;
    using std::min;
    const T zero = ir::literal(a, 0.0), one = ir::literal(a, 1.0);
    const FoldMembers<T> members = foldMembers(a, lead);
    auto running = [&](T p) { // odd: the far side's ink counts back from the fold
        const T ink = foldRunningInk(abs(p), members);
        return ir::select(ir::lessThan(p, zero), zero - ink, ink);
    };
    const T steep = max(abs(along), abs(across)), shallow = min(abs(along), abs(across));
    // Held off 0 by a share of the values it spans, so that a part the members run along
    // reads the ink at its centre line (a difference over a span below float's steps of P).
    const T span = max(steep, (abs(centre) + one) * 1e-4);
    T sum = zero;
    for (int i = 0; i < kFoldSlices; ++i) {
        const T mid = centre + shallow * ((i + 0.5) / kFoldSlices - 0.5);
        sum = sum + (running(mid + span * 0.5) - running(mid - span * 0.5)) / span;
    }
    return min(max(sum * (1.0 / kFoldSlices), zero), one);
}

} // namespace moire::lower
