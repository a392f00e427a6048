// The characters of a superposition (spec §4.2-4.4). Any integer combination
// k1 idx1 + k2 idx2 of two layers' index fields is a candidate beat; the one the eye reads as
// the moiré is the one of least merit mu_k = |k1 k2| eta_k, where the heterodyne ratio eta_k
// (Eq. 11) says how fast the beat changes against its carriers and |k1 k2| prices the
// contrast its harmonics lose. This file finds that character per pixel:
//  - the six characters with |k_i| <= 2 are always scanned (the floor);
//  - the lattice of beat frequencies {k1 g1 + k2 g2} is Lagrange-Gauss reduced with the
//    integer coordinates carried along, in a fixed eight steps (straight-line code: a step
//    that cannot shrink the basis changes nothing, so no step needs to know whether an
//    earlier one finished), and the merit is scanned over every vector the steps make and
//    small combinations of the reduced basis, since the weighted winner need not be the
//    shortest vector (§4.3);
//  - a stack of three or more scans every pair among its three topmost layers and the
//    zero-sum ternary characters, and keeps the global winner (§4.4).
// A lattice layer indexes its points by a pair (u, v), its two generators (§3.6, §4.1), so
// its characters range over integer combinations of both: k1 (a u + b v) + k2 idx2 + ...
// The search treats the lattice as its first-order row families a u + b v, (a, b) one of
// kLatticeRows: the generators u and v and the diagonals u + v and u - v (each a line family
// through every point of the lattice; for the A2 lattices u + v is the third row of the
// same pitch). A lattice's harmonic (a, b) is priced by its order max(|a|, |b|), the
// lattice's reading of the 1 / m decay: the harmonic m (a, b) of a first-order row costs m,
// as a row family priced like any one-index family would. Everything above then runs over
// one row per layer: a pair of layers scans every row of the one against every row of the
// other, a ternary one row of each. A lattice's own rows never beat with each other: a
// combination of one layer's generators alone is a row family of that layer, drawn by it
// alone, not a beat of the superposition, so a lattice by itself has no character, as any
// sole layer has none.
// Finer rows (2u + v, ...) are left out: their harmonics are of order 2 and more, they carry
// less of the lattice's ink, and each would cost as much again as the four rows
// (LatticeCharacters_test holds the search to a brute force over every harmonic of order up
// to 6, finer rows included, where a first-order row wins).
// Written once as templates over the number type: instantiated with ir::BuiltValue they build
// the kernel's IR (Characters.cpp); with double they are what experiments/ measures.
#pragma once

#include "compiler/ir/BuiltValue.h"
#include "compiler/ir/Plane.h"
#include "compiler/ir/Semantics.h"
#include "compiler/lower/LayerPipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

namespace moire::lower {

// The fringe criterion: a fringe exists where min mu_k <= 1/4 (§4.2).
constexpr double kFringeMerit = 0.25;
// The slowest beat the merit tells apart: eta_k below this counts as this. A beat wider than a
// thousand carrier periods is as broad as any frame shows, and without the floor an exactly
// commensurate pair (pitches 10 and 10.5 are 21:20) would crown the beat of order (21, -20),
// eta 0, over the (1, -1) fringe the eye sees: the weight |k1 k2| can only rank beats whose
// slowness it does not multiply by zero. So a character of weight 250 or more is never a
// fringe (mu >= 1/4), which is what its contrast, under 1/250, says too.
constexpr double kEtaFloor = 1e-3;
// The merit reported where no character is a beat at all (a sole layer, a zero gradient).
constexpr double kNoCharacter = 1e30;
// Lagrange-Gauss steps. The reduction converges geometrically, so eight reach the shortest
// vector of a pair whose gradients are not nearly collinear (Characters_test holds random
// pairs to brute force); on nearly collinear ones the steps walk the pitch ratio's continued
// fraction, and by the eighth they are at orders far past the weight 250 at which kEtaFloor
// rules out a fringe (on the golden ratio, whose terms grow slowest, at (1597, -987)).
constexpr int kReductionSteps = 8;
// Combinations i a + j c of the reduced basis (a, c) scanned, |i|, |j| <= this, beside every
// vector the steps make. Measured by experiments/order_cap's pairs: with twists within +-5
// degrees, the final basis alone misses 9, 6 and 3 visible fringes at windows of 2, 3 and 4
// (7 at 2 within +-10 degrees); with the steps' vectors scanned, a window of 1 misses none
// (within +-0.5, 2, 5, 10 and 30 degrees alike).
constexpr int kCharacterWindow = 1;
// One reduction step subtracts at most this multiple. It matters only on (nearly) collinear
// gradients, where the basis is all but rank one and an unbounded multiple would carry the
// coordinates past what a float holds exactly; the beats it leaves out are of orders whose
// contrast is gone (1 / |k1 k2| < 1e-7).
constexpr double kStepMultipleCap = 4096.0;

// The six characters with |k_i| <= 2 and no zero (k and -k are one character; (2, 2) is
// (1, 1) at four times the merit).
inline constexpr std::array<std::array<int, 2>, 6> kFloorCharacters = {
    {{1, -1}, {1, 1}, {2, -1}, {2, 1}, {1, -2}, {1, 2}}};
// A lattice's row families, as coefficients (a, b) of its generators (u, v): row r is the
// index field a u + b v, in this order (ties go to the earlier row).
inline constexpr std::array<std::array<int, 2>, 4> kLatticeRows = {
    {{1, 0}, {0, 1}, {1, 1}, {1, -1}}};
// The zero-sum ternary characters scanned for three layers: the permutations of (1, 1, -2).
inline constexpr std::array<std::array<int, 3>, 3> kTernaryCharacters = {
    {{1, 1, -2}, {1, -2, 1}, {-2, 1, 1}}};

template <class T>
using Grad = ir::Vec2T<T>; // an index gradient, index units per world unit

// eta_k (Eq. 11): |k1 g1 + k2 g2| over half of |k1 g1 - k2 g2|, the mean carrier in the
// relabelling that brings the two carriers together.
template <class T>
inline T heterodyneRatio(T k1, T k2, Grad<T> g1, Grad<T> g2) {
    using std::hypot, std::max;
    T beat = hypot(k1 * g1.x + k2 * g2.x, k1 * g1.y + k2 * g2.y);
    T mean = hypot(k1 * g1.x - k2 * g2.x, k1 * g1.y - k2 * g2.y) * 0.5;
    return beat / max(mean, ir::literal(mean, ir::kTiny));
}

// mu_k = |k1 k2| max(eta_k, kEtaFloor) (Eq. 12, with the floor above). A character with a
// zero coefficient is one layer alone, not a beat: it gets kNoCharacter rather than the merit
// 0 its weight would give it.
template <class T>
inline T characterMerit(T k1, T k2, Grad<T> g1, Grad<T> g2) {
    using std::abs, std::max;
    T weight = abs(k1 * k2);
    T eta = heterodyneRatio(k1, k2, g1, g2);
    T mu = weight * max(eta, ir::literal(eta, kEtaFloor));
    return ir::select(ir::lessThan(ir::literal(weight, 0.5), weight), mu,
                      ir::literal(weight, kNoCharacter));
}

// A ternary character k (zero-sum) of three gradients: the beat sum k_i g_i against half the
// carrier sum |k_i| g_i, weighted by |k1 k2 k3|. For two layers and a difference character
// (k1 > 0 > k2) this is Eq. 11-12 exactly; with three it prices the beat between beats of
// §4.4 the same way (harmonics |k_i| of each layer, contrast 1 / |k1 k2 k3|).
template <class T>
inline T ternaryMerit(const std::array<int, 3>& k, const std::array<Grad<T>, 3>& g) {
    using std::hypot, std::max;
    T bx = g[0].x * double(k[0]) + g[1].x * double(k[1]) + g[2].x * double(k[2]);
    T by = g[0].y * double(k[0]) + g[1].y * double(k[1]) + g[2].y * double(k[2]);
    T cx = g[0].x * double(std::abs(k[0])) + g[1].x * double(std::abs(k[1])) +
           g[2].x * double(std::abs(k[2]));
    T cy = g[0].y * double(std::abs(k[0])) + g[1].y * double(std::abs(k[1])) +
           g[2].y * double(std::abs(k[2]));
    T mean = hypot(cx, cy) * 0.5;
    T eta = hypot(bx, by) / max(mean, ir::literal(mean, ir::kTiny));
    return max(eta, ir::literal(eta, kEtaFloor)) * double(std::abs(k[0] * k[1] * k[2]));
}

// A lattice vector of beat frequencies and its integer coordinates: (x, y) = k1 g1 + k2 g2.
template <class T>
struct BeatT {
    T x, y, k1, k2;
};

template <class T, class C>
inline BeatT<T> chooseBeat(C cond, const BeatT<T>& a, const BeatT<T>& b) {
    return {ir::select(cond, a.x, b.x), ir::select(cond, a.y, b.y), ir::select(cond, a.k1, b.k1),
            ir::select(cond, a.k2, b.k2)};
}

template <class T>
inline T lengthSquared(const BeatT<T>& v) {
    return v.x * v.x + v.y * v.y;
}

// Lagrange-Gauss reduction of the lattice {k1 g1 + k2 g2}, unrolled: each step keeps the
// shorter vector s, takes from the other the nearest multiple of s (round(<s, l> / |s|^2),
// the step of Euclid's algorithm), and carries the coordinates along. Returns the reduced
// basis, shortest first.
template <class T, class Visit>
inline std::array<BeatT<T>, 2> reduceBeats(Grad<T> g1, Grad<T> g2, Visit&& visit) {
    using std::floor, std::max, std::min;
    T one = ir::literal(g1.x, 1.0), zero = ir::literal(g1.x, 0.0);
    BeatT<T> a{g1.x, g1.y, one, zero};
    BeatT<T> c{g2.x, g2.y, zero, one};
    for (int step = 0; step < kReductionSteps; ++step) {
        auto swap = ir::lessThan(lengthSquared(c), lengthSquared(a));
        BeatT<T> s = chooseBeat(swap, c, a);
        BeatT<T> l = chooseBeat(swap, a, c);
        T len2 = max(lengthSquared(s), ir::literal(one, ir::kTiny));
        T m = floor((s.x * l.x + s.y * l.y) / len2 + 0.5);
        m = min(max(m, ir::literal(m, -kStepMultipleCap)), ir::literal(m, kStepMultipleCap));
        a = s;
        c = {l.x - m * s.x, l.y - m * s.y, l.k1 - m * s.k1, l.k2 - m * s.k2};
        visit(a, c);
    }
    auto swap = ir::lessThan(lengthSquared(c), lengthSquared(a));
    return {chooseBeat(swap, c, a), chooseBeat(swap, a, c)};
}

// The winning character of a pair: its merit and coefficients (integers held as numbers).
template <class T>
struct PairCharacterT {
    T mu, k1, k2;
};

template <class T>
inline void considerCharacter(PairCharacterT<T>& best, T k1, T k2, Grad<T> g1, Grad<T> g2) {
    T mu = characterMerit(k1, k2, g1, g2);
    auto better = ir::lessThan(mu, best.mu);
    best = {ir::select(better, mu, best.mu), ir::select(better, k1, best.k1),
            ir::select(better, k2, best.k2)};
}

// i x + j y for small integers i, j, without building products by 0 or 1.
template <class T>
inline T smallCombination(int i, T x, int j, T y) {
    auto term = [](int n, T v) { return n == 1 ? v : (n == -1 ? -v : v * double(n)); };
    if (i == 0) return term(j, y);
    if (j == 0) return term(i, x);
    return term(i, x) + term(j, y);
}

// min over k of mu_k for one pair: the floor, then the window of the reduced basis. Ties go
// to the character scanned first, so the floor's low orders win them.
template <class T>
inline PairCharacterT<T> bestPairCharacter(Grad<T> g1, Grad<T> g2, int window = kCharacterWindow) {
    T zero = ir::literal(g1.x, 0.0);
    PairCharacterT<T> best{ir::literal(zero, kNoCharacter), zero, zero};
    for (const auto& k : kFloorCharacters)
        considerCharacter(best, ir::literal(zero, k[0]), ir::literal(zero, k[1]), g1, g2);
    // Every vector a step makes is scanned, not only the final basis: on nearly collinear
    // gradients the steps walk the pitch ratio's continued fraction, and the weighted winner
    // (a low convergent such as (3, -1)) is passed on the way to a shorter vector of far
    // higher order.
    std::array<BeatT<T>, 2> basis = reduceBeats(g1, g2, [&](const BeatT<T>&, const BeatT<T>& made) {
        considerCharacter(best, made.k1, made.k2, g1, g2);
    });
    const BeatT<T>& a = basis[0];
    const BeatT<T>& c = basis[1];
    for (int j = 0; j <= window; ++j)
        for (int i = -window; i <= window; ++i) {
            if (j == 0 && i <= 0) continue; // k and -k are one character
            considerCharacter(best, smallCombination(i, a.k1, j, c.k1),
                              smallCombination(i, a.k2, j, c.k2), g1, g2);
        }
    return best;
}

// The winner over a stack's (up to) three topmost layers, given bottom to top: coefficients
// k[i] of layer i, zero for a layer the character leaves out, and row[i], which of layer
// i's index fields the coefficient multiplies (always 0 for a one-index layer; for a lattice
// the position in kLatticeRows).
template <class T>
struct StackCharacterT {
    T mu;
    std::array<T, 3> k;
    std::array<T, 3> row;
};

// The general search: `rows[i]` holds layer i's index-field gradients (one for a one-index
// family, one per row family for a lattice), at least one layer, each with at least one row.
// The pairs go topmost first and, within a pair of layers, row by row (ties go to the
// earlier); then the zero-sum ternaries over one row of each of three layers.
template <class T>
inline StackCharacterT<T> bestStackCharacterOfRows(std::span<const std::vector<Grad<T>>> rows,
                                                   int window = kCharacterWindow) {
    T zero = ir::literal(rows[0][0].x, 0.0);
    StackCharacterT<T> best{
        ir::literal(zero, kNoCharacter), {zero, zero, zero}, {zero, zero, zero}};
    if (rows.size() < 2) return best;
    const size_t n = std::min<size_t>(rows.size(), 3);
    std::span<const std::vector<Grad<T>>> top = rows.subspan(rows.size() - n);
    auto keep = [&](T mu, const std::array<T, 3>& k, const std::array<size_t, 3>& row) {
        auto better = ir::lessThan(mu, best.mu);
        best.mu = ir::select(better, mu, best.mu);
        for (size_t i = 0; i < n; ++i) {
            best.k[i] = ir::select(better, k[i], best.k[i]);
            best.row[i] = ir::select(better, ir::literal(zero, double(row[i])), best.row[i]);
        }
    };
    for (size_t hi = n; hi-- > 1;)
        for (size_t lo = hi; lo-- > 0;)
            for (size_t ra = 0; ra < top[lo].size(); ++ra)
                for (size_t rb = 0; rb < top[hi].size(); ++rb) {
                    PairCharacterT<T> p = bestPairCharacter(top[lo][ra], top[hi][rb], window);
                    std::array<T, 3> k = {zero, zero, zero};
                    std::array<size_t, 3> row = {0, 0, 0};
                    k[lo] = p.k1;
                    k[hi] = p.k2;
                    row[lo] = ra;
                    row[hi] = rb;
                    keep(p.mu, k, row);
                }
    if (n == 3) {
        for (size_t r0 = 0; r0 < top[0].size(); ++r0)
            for (size_t r1 = 0; r1 < top[1].size(); ++r1)
                for (size_t r2 = 0; r2 < top[2].size(); ++r2) {
                    std::array<Grad<T>, 3> g3 = {top[0][r0], top[1][r1], top[2][r2]};
                    for (const auto& k : kTernaryCharacters) {
                        std::array<T, 3> kt = {ir::literal(zero, k[0]), ir::literal(zero, k[1]),
                                               ir::literal(zero, k[2])};
                        keep(ternaryMerit(k, g3), kt, {r0, r1, r2});
                    }
                }
    }
    return best;
}

// One-index layers only: `g` holds each layer's index gradient, at least one layer.
template <class T>
inline StackCharacterT<T> bestStackCharacter(std::span<const Grad<T>> g,
                                             int window = kCharacterWindow) {
    std::vector<std::vector<Grad<T>>> rows;
    for (const Grad<T>& gi : g) rows.push_back({gi});
    return bestStackCharacterOfRows<T>(rows, window);
}

// A lattice's row gradients from its generators' gradients gu, gv (kLatticeRows' order).
template <class T>
inline std::vector<Grad<T>> latticeRowGradients(Grad<T> gu, Grad<T> gv) {
    std::vector<Grad<T>> out;
    for (const auto& r : kLatticeRows)
        out.push_back(
            {smallCombination(r[0], gu.x, r[1], gv.x), smallCombination(r[0], gu.y, r[1], gv.y)});
    return out;
}

// ---- The IR instantiation ----

// A stack's winning character at the pixel: its merit (kNoCharacter where there is no pair)
// and its coefficients over `layer[0..count)`, indices into the layers it was given.
// For a lattice layer (genU set) the coefficient multiplies one of its row families,
// rowU[i] u + rowV[i] v (per pixel: which row wins varies), so the layer's term is
// k[i] (rowU[i] genU + rowV[i] genV), and (k rowU, k rowV) are its coefficients on its two
// generators (characterGenerators); on a one-index layer rowU and rowV are kNoValue.
struct Character {
    ir::ValueId mu = ir::kNoValue;
    std::array<ir::ValueId, 3> k = {ir::kNoValue, ir::kNoValue, ir::kNoValue};
    std::array<int, 3> layer = {-1, -1, -1};
    int count = 0;
    std::array<ir::ValueId, 3> rowU = {ir::kNoValue, ir::kNoValue, ir::kNoValue};
    std::array<ir::ValueId, 3> rowV = {ir::kNoValue, ir::kNoValue, ir::kNoValue};
};

// An index field and its gradient, per world unit.
struct IndexField {
    ir::ValueId value, gradX, gradY;
};

// The index fields the search scans for one layer: its index, or for a lattice its row
// families (kLatticeRows over genU, genV). A layer without an index gradient (gradX =
// kNoValue) counts as gradient zero: it beats with nothing.
std::vector<IndexField> characterRows(ir::Builder& b, const LayerFields& layer);

// The winner for `layers` (bottom to top; the three topmost are scanned), lattices included.
Character stackCharacter(ir::Builder& b, std::span<const LayerFields> layers);

// Slot i's coefficients on layer c.layer[i]'s index fields: (k, 0) on a one-index layer's
// index, (k rowU, k rowV) on a lattice's generators (genU, genV). A sweep that keeps the
// character is chosen orthogonal to these (§4.4: a lattice's index is a pair, and which
// combination of its generators rides the sweep is this per-pixel choice).
std::array<ir::ValueId, 2> characterGenerators(ir::Builder& b, const Character& c, int i);

// The winner's combination sum k_i idx_i and its gradient, per world unit.
struct Combination {
    ir::ValueId value, gradX, gradY;
};
Combination characterCombination(ir::Builder& b, const Character& c,
                                 std::span<const LayerFields> layers);

// The winner's order sum |k_i| (2 for the first-order difference and sum beats; a lattice's
// row counts as one index field).
ir::ValueId characterOrder(ir::Builder& b, const Character& c);

} // namespace moire::lower
