#include "compiler/lower/Compose.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/lower/RatioView.h"

#include <algorithm>
#include <optional>
#include <span>

namespace moire::lower {

using ir::Op;
using ir::ValueId;

Compose::Compose(ir::Builder& b, ViewMode mode, const Vals& background,
                 const EnvelopeSettings& envelope, ir::ValueId overlayPixel)
    : b_(b), mode_(mode),
      paper_(paper(b, background[0], background[1], background[2], background[3])), acc_(paper_),
      settings_(envelope), overlayPixel_(overlayPixel), zero_(b.constF(0.0)), unresolved_(zero_) {}

void Compose::layer(const LayerInk& ink) {
    if (ink.sampling != ir::kNoValue) unresolved_ = b_.max(unresolved_, ink.sampling);
    b_.setLoc(ink.where);
    // The pattern is drawn in every view (the split shows it; elsewhere what is not used
    // is removed as dead code).
    // Under the mean filter (pixel set) the stroke as written averaged over the pixel: by its
    // index where the family gives one to average along, else from its distance, and handed
    // over to the family's crowd where it estimates one (layerMeanInk).
    ValueId stroke = ink.pixel.size == ir::kNoValue
                         ? strokeInk(b_, ink.fields.distance, ink.band)
                         : layerMeanInk(b_, ink.fields, ink.halfWidth, ink.pixel);
    // A lattice's edges are whole lines laid as independent inks: where they cross within
    // the pixel, their overlap (StrokePairs.h, strandCrossings), as far as the crowded
    // reading is taken (`engaged`: the triangle lattice's edges are read over the pixel,
    // overlaps and all, where its rows stand under 1.4 a pixel, LatticeCrowd.cpp).
    std::vector<StrokeAcross> strands;
    if (ink.pixel.size != ir::kNoValue && joinsAsStrands(ink.fields.crowd)) {
        // Each strand is a phase family's footprint, whose stroke across is always known.
        strands = strandStrokes(b_, ink.fields.crowd, ink.halfWidth, ink.pixel);
        MOIRE_CHECK(strands.size() == ink.fields.crowd.strands.size(),
                    "a lattice's strands are phase footprints");
        ValueId crossings = strandCrossings(b_, strands, ink.fields.crowd.strandMeans);
        if (strands.size() == 3 && ink.fields.crowd.engaged != ir::kNoValue)
            crossings = b_.mul(crossings, ink.fields.crowd.engaged);
        stroke = b_.clamp(b_.add(stroke, crossings), zero_, b_.constF(1.0));
    }
    ValueId cov = inkCoverage(b_, stroke, ink.opacity, ink.color[3]);
    // Under the mean filter, consecutive phase families form a run whose union is taken
    // together (FineUnion.h); any other layer ends the run before it is laid.
    const bool filtered = ink.pixel.size != ir::kNoValue;
    const bool lattice = filtered && joinsAsLattice(ink.fields.crowd);
    const bool byDistance = filtered && joinsByDistance(ink.fields.crowd);
    const bool fine = lattice || byDistance ||
                      (filtered && joinsFineUnion(ink.fields.footprint, ink.fields.sample));
    // A run with a lattice, or a family given by its distance, is a pair: its correlation is
    // its strands' (FineUnion.h), or a pair's in closed form, which the sweep of a longer run
    // does not know. Closed at two, it hands its last layer on to the next run, so that every
    // two consecutive fine layers are correlated (a lattice under two fine phase families
    // leaves their beat to the second pair).
    const bool anyPairsOnly =
        std::any_of(run_.begin(), run_.end(), [](const FineLayer& l) { return l.pairsOnly(); });
    if (!fine) {
        closeRun();
    } else if (run_.size() >= 2 && (lattice || byDistance || anyPairsOnly)) {
        const FineLayer last = run_.back();
        const Ink beneathLast = lastUnder_;
        closeRun();
        run_.push_back(last);
        runUnder_ = beneathLast;
    }
    if (fine && run_.empty()) runUnder_ = acc_;
    const Ink under = acc_;
    if (fine) lastUnder_ = under;
    acc_ = inkOver(b_, acc_, ink.color[0], ink.color[1], ink.color[2], cov);
    if (ink.pixel.size != ir::kNoValue) meetStrokes(ink, cov, under, strands);
    if (fine) {
        // No antialias band of the pattern's: the sweep averages the pixel, and its taps' own
        // band (Envelope.h, kTapBand) is the only one the stroke's edge needs.
        FineLayer l{EnvelopeLayer{ink.fields.sample, ink.halfWidth, zero_, ink.color, ink.opacity,
                                  ink.spacing, ink.fields.gradX, ink.fields.gradY},
                    ink.fields.footprint,
                    {},
                    ir::kNoValue,
                    std::nullopt,
                    stroke};
        if (lattice) {
            for (size_t i = 0; i < ink.fields.crowd.strands.size(); ++i)
                l.strands.push_back({ink.fields.crowd.strands[i], ink.fields.crowd.strandMeans[i]});
            l.strandsOn = ink.fields.crowd.strandsOn;
            l.shape = ink.fields.crowd.shape;
        } else if (byDistance) {
            // As a phase family by the index its crowd runs by, the stroke's half-width across
            // its members in world units.
            const CrowdEstimate::Runs& runs = *ink.fields.crowd.runs;
            l.sweep.halfWidth = runs.halfWidth;
            l.sweep.gradX = runs.footprint.gradX;
            l.sweep.gradY = runs.footprint.gradY;
            l.footprint = runs.footprint;
            l.byDistance = true;
            // One strand where the members run one way (the layer's ink); a grid's two or
            // three ways, each with its own mean (0 for a third that stands for no lines),
            // where they run two or three (FineUnion.cpp reads them then).
            const ValueId grid = b_.gt(runs.twoWays, zero_);
            l.strands.push_back({runs.footprint, b_.select(grid, runs.means[0], stroke)});
            l.strands.push_back({runs.second, b_.select(grid, runs.means[1], zero_)});
            l.strands.push_back({runs.third, b_.select(grid, runs.means[2], zero_)});
            l.twoWays = runs.twoWays;
            l.shape = runs.screen;
        } else {
            l.strands.push_back({ink.fields.footprint, stroke});
        }
        run_.push_back(l);
        runPixel_ = ink.pixel;
    }
    fields_.push_back(ink.fields);
    if (!sema::viewSweeps(mode_)) return;
    EnvelopeLayer l{ink.fields.sample, ink.halfWidth, ink.band.a,       ink.color,
                    ink.opacity,       ink.spacing,   ink.fields.gradX, ink.fields.gradY};
    // A family without a phase sample is reported before the kernel is used
    // (LoweredScene::unsweepable); its ink then stays put while the others sweep.
    if (l.sample.z == ir::kNoValue)
        l.sample = {ink.fields.distance,
                    b_.constF(kNoMember),
                    b_.constF(kNoMember),
                    zero_,
                    std::nullopt,
                    std::nullopt,
                    nullptr};
    sweep_.push_back(l);
}

// The most strokes beneath a layer that are met with its own (a layer's nearest member, and
// each of a lattice's lines): each pair costs a covariance at every pixel, and a stroke far
// down the stack is mostly covered over.
constexpr size_t kMostStrokesMet = 6;

void Compose::meetStrokes(const LayerInk& ink, ValueId cov, const Ink& under,
                          const std::vector<StrokeAcross>& strands) {
    // The layer's strokes: its nearest member's, and a lattice's lines (strandStrokes), each
    // of which meets a later stroke with the share of the pixel its other lines leave
    // (the union's derivative in that line's ink, 1 - m_j over the others).
    struct Mine {
        StrokeAcross stroke;
        ValueId share;
    };
    std::vector<Mine> mine;
    if (std::optional<StrokeAcross> s = strokeAcross(b_, ink.fields, ink.halfWidth, ink.pixel))
        mine.push_back({*s, b_.constF(1.0)});
    for (size_t i = 0; i < strands.size(); ++i) {
        ValueId share = b_.constF(1.0);
        for (size_t j = 0; j < strands.size(); ++j)
            if (j != i)
                share = b_.mul(share, b_.sub(b_.constF(1.0), ink.fields.crowd.strandMeans[j]));
        mine.push_back({strands[i], share});
    }
    // k_j: the layer's coverage per unit of its ink.
    ValueId k = inkCoverage(b_, b_.constF(1.0), ink.opacity, ink.color[3]);
    if (!mine.empty() && !laid_.empty()) {
        // One pair's correction added to `add`: laid stroke l met by the layer's stroke m.
        auto meetPair = [&](Ink add, const Laid& l, const Mine& m) {
            // Behind a branch: most pixels meet one stroke or none.
            ValueId meet = b_.emit(Op::And, {l.stroke.touches, m.stroke.touches});
            ValueId cov = b_.ifThenElse(
                meet,
                [&] { return std::vector<ValueId>{strokeCovariance(b_, l.stroke, m.stroke)}; },
                [&] { return std::vector<ValueId>{zero_}; })[0];
            // Where one layer's members crowd and the other's do not, the crowded one's
            // members as periodic strokes against the other's stroke.
            cov = b_.add(cov, mixedPairCovariance(b_, l.stroke, m.stroke));
            ValueId t = b_.mul(b_.mul(k, m.share), cov);
            return Ink{b_.add(add.r, b_.mul(t, l.pending.r)), b_.add(add.g, b_.mul(t, l.pending.g)),
                       b_.add(add.b, b_.mul(t, l.pending.b)),
                       b_.add(add.a, b_.mul(t, l.pending.a))};
        };
        Ink add{zero_, zero_, zero_, zero_};
        if (laid_.size() >= 2 && laidAlike()) {
            // Strokes laid alike (every field present in each or in none) are met in a loop,
            // in the order they were laid, each read from the list by its place: a pair's terms
            // are built into the kernel once for the layer, where written out for each stroke
            // beneath they were a third of a four-layer scene's kernel (examples/two_fields).
            const double count = double(laid_.size());
            std::vector<ValueId> res = b_.loop(
                {zero_, zero_, zero_, zero_, zero_},
                [&](std::span<const ValueId> v) {
                    return std::vector<ValueId>{b_.lt(v[0], b_.constF(count))};
                },
                [&](std::span<const ValueId> v) {
                    const Laid l = laidAt(v[0]);
                    Ink sum{v[1], v[2], v[3], v[4]};
                    for (const Mine& m : mine) sum = meetPair(sum, l, m);
                    return std::vector<ValueId>{b_.add(v[0], b_.constF(1.0)), sum.r, sum.g, sum.b,
                                                sum.a};
                });
            add = {res[1], res[2], res[3], res[4]};
        } else {
            for (const Laid& l : laid_)
                for (const Mine& m : mine) add = meetPair(add, l, m);
        }
        acc_ = addCorrection(b_, acc_, add, b_.constF(1.0));
    }
    // Every layer laid scales what the strokes beneath it still add by what it leaves showing.
    ValueId keep = b_.sub(b_.constF(1.0), cov);
    for (Laid& l : laid_)
        l.pending = {b_.mul(l.pending.r, keep), b_.mul(l.pending.g, keep),
                     b_.mul(l.pending.b, keep), b_.mul(l.pending.a, keep)};
    for (const Mine& m : mine) {
        if (laid_.size() == kMostStrokesMet) laid_.erase(laid_.begin());
        auto pending = [&](ValueId beneath, ValueId colour) {
            return b_.mul(b_.mul(k, m.share), b_.sub(beneath, colour));
        };
        laid_.push_back({m.stroke,
                         {pending(under.r, ink.color[0]), pending(under.g, ink.color[1]),
                          pending(under.b, ink.color[2]), pending(under.a, b_.constF(1.0))}});
    }
}

namespace {
// Every field of a laid stroke and of its pending ink, in one order (laidAlike, laidAt).
template <class Visit>
void eachField(StrokeAcross& s, Ink& pending, Visit visit) {
    for (ValueId* f :
         {&s.nu, &s.nv, &s.s, &s.h, &s.weight, &s.touches, &s.index, &s.gu, &s.gv, &s.w,
          &s.unresolved, &s.disc, &pending.r, &pending.g, &pending.b, &pending.a})
        visit(*f);
}
} // namespace

bool Compose::laidAlike() const {
    auto present = [](Laid l) {
        std::vector<bool> out;
        eachField(l.stroke, l.pending, [&](ValueId v) { out.push_back(v != ir::kNoValue); });
        return out;
    };
    const std::vector<bool> first = present(laid_.front());
    return std::all_of(laid_.begin(), laid_.end(),
                       [&](const Laid& l) { return present(l) == first; });
}

// The laid stroke at place `at` (a value in the kernel), each field picked from the list.
Compose::Laid Compose::laidAt(ValueId at) {
    std::vector<Laid> all = laid_;
    Laid out = all.front();
    std::vector<std::vector<ValueId>> columns;
    for (Laid& l : all) {
        std::vector<ValueId> column;
        eachField(l.stroke, l.pending, [&](ValueId v) { column.push_back(v); });
        columns.push_back(column);
    }
    size_t field = 0;
    eachField(out.stroke, out.pending, [&](ValueId& v) {
        if (v != ir::kNoValue) {
            std::vector<ValueId> column;
            for (const std::vector<ValueId>& fields : columns) column.push_back(fields[field]);
            v = b_.pick(at, column);
        }
        ++field;
    });
    return out;
}

void Compose::closeRun() {
    // The layers of the run are in acc_ already, each laid over the others (the union of their
    // means); the union adds their correlation where their beat shows (FineUnion.cpp).
    if (run_.size() >= 2) acc_ = fineUnion(b_, runUnder_, acc_, run_, runPixel_);
    run_.clear();
}

Ink Compose::envelope() {
    const bool lattice = std::any_of(sweep_.begin(), sweep_.end(), [](const EnvelopeLayer& l) {
        return l.sample.lattice.has_value();
    });
    const bool oneIndex = std::any_of(sweep_.begin(), sweep_.end(),
                                      [](const EnvelopeLayer& l) { return !l.sample.lattice; });
    if (lattice && oneIndex) {
        std::vector<EnvelopeLayer> layers = sweep_;
        rankTwoRides(b_, stackCharacter(b_, fields_), layers);
        return envelopeInk(b_, paper_, layers, settings_);
    }
    return envelopeInk(b_, paper_, sweep_, settings_);
}

// Fig. 1's layout: the pattern left of the frame's middle, the envelope right, and a dashed
// rule between them (1.5 pixels wide, antialiased, in dashes of 6 pixels every 12).
Ink Compose::split() {
    ValueId px = b_.leaf(Op::PixelX);
    ValueId middle = b_.mul(b_.leaf(Op::ImageW), b_.constF(0.5));
    std::vector<ValueId> right = b_.ifThenElse(
        b_.emit(Op::Ge, {px, middle}),
        [&] {
            Ink e = envelope();
            return std::vector<ValueId>{e.r, e.g, e.b, e.a};
        },
        [&] {
            return std::vector<ValueId>{acc_.r, acc_.g, acc_.b, acc_.a};
        });
    Ink out{right[0], right[1], right[2], right[3]};
    ValueId across = b_.abs(b_.sub(px, middle));
    ValueId rule = b_.clamp(b_.sub(b_.constF(1.25), across), zero_, b_.constF(1.0));
    ValueId dash =
        b_.lt(b_.emit(Op::Fract, {b_.div(b_.leaf(Op::PixelY), b_.constF(12.0))}), b_.constF(0.5));
    rule = b_.select(dash, b_.mul(rule, b_.constF(0.7)), zero_);
    ValueId grey = b_.constF(0.25);
    return inkOver(b_, out, grey, grey, grey, rule);
}

void Compose::output(const std::function<Vals()>& unresolvedTint) {
    closeRun();
    // The stack's winning character, for the ratio view and the overlay (Characters.h).
    std::optional<Character> winner;
    auto character = [&]() -> const Character& {
        if (!winner) winner = stackCharacter(b_, fields_);
        return *winner;
    };
    Ink shown = acc_;
    switch (mode_) {
    case ViewMode::Pattern:
        break;
    case ViewMode::Envelope:
        shown = envelope();
        break;
    case ViewMode::Split:
        shown = split();
        break;
    case ViewMode::Ratio:
        shown = ratioViewInk(b_, character());
        break;
    }
    // The sampling limit (§10.4): a carrier of pitch s cannot show fringes much finer than
    // 3 s, so where an encoded field is that steep the scene's `unresolved` tint is laid
    // over everything (transparent unless the scene sets it).
    if (unresolved_ != zero_ && unresolvedTint) {
        Vals tint = unresolvedTint();
        ValueId mark = b_.smoothstep(b_.constF(0.30), b_.constF(0.37), unresolved_);
        shown = inkOver(b_, shown, tint[0], tint[1], tint[2],
                        b_.mul(mark, b_.clamp(tint[3], zero_, b_.constF(1.0))));
    }
    // The fringe curves go over everything, as Fig. 5d draws them over the averaged ink.
    if (overlayPixel_ != ir::kNoValue)
        shown = overlayFringes(b_, shown, character(), fields_, overlayPixel_);
    Ink out = unpremultiply(b_, shown);
    b_.output(0, out.r);
    b_.output(1, out.g);
    b_.output(2, out.b);
    b_.output(3, out.a);
}

} // namespace moire::lower
