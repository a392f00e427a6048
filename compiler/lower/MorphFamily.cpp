#include "compiler/lower/MorphFamily.h"

namespace moire::lower {

using ir::Op;
using ir::ValueId;

// A morph (§8.3). The timing's pass is cut into one equal share per family: family k
// holds through its share and, in the share's last morph_time seconds, travels to the
// next (eased cubic in and out). A looping timing travels from the last family back to
// the first, so the cycle closes; once and pingpong hold the last.
//
// What travels is the geometry, not the ink: where every family has a phase, the two
// phases are interpolated and the blend is drawn as a family of its own (Eq. 5 on the
// blend), so each member is one stroke moving from one shape to the other. For the
// concentric families, whose phases have unit gradient, that is exactly the signed
// distances to the member interpolated. Walking families interpolate their radii the
// same way inside the search. Unsigned distances to the nearest member would not do:
// half-way, a point on a member of one family but between members of the other is at
// half a gap from both, and the strokes break up instead of travelling. Only a morph that
// mixes kinds (a lattice, a pencil, a walking family with one that cannot walk) falls
// back to interpolating the two distances; its phase sample (for the views that sweep)
// is then its members' samples, blended tap by tap.
LayerFields morphFields(LayerLowering& layers, const sema::CheckedLayer& layer,
                        const LayerFrame& lf, const StrokeBand& band, const Encoding& enc,
                        bool wantIndex) {
    SceneContext& ctx = layers.context();
    ir::Builder& b = ctx.b;
    std::vector<BoundFamily> members;
    for (const sema::CheckedLayer::Member& m : layer.morph)
        members.push_back(layers.bind(m.family, m.args));
    b.setLoc(layer.decl->range.begin);
    const double count = static_cast<double>(members.size());
    const sema::TimingMode mode = ctx.scene.timings.at(layer.morphTiming).mode;
    ValueId raw = ctx.timings.progress(layer.morphTiming).raw;
    ValueId along = b.mul(raw, b.constF(count));
    ValueId k = b.min(b.floor(along), b.constF(count - 1.0));
    ValueId share = b.div(ctx.timings.period(layer.morphTiming), b.constF(count));
    ValueId seconds = b.mul(b.sub(along, k), share);
    // A change longer than a share would still be under way when the next one starts.
    ValueId length = b.clamp(ctx.layerProp(layer, "morph_time")[0], b.constF(1e-6), share);
    ValueId u =
        b.clamp(b.div(b.sub(seconds, b.sub(share, length)), length), b.constF(0.0), b.constF(1.0));
    ValueId w = ctx.timings.ease("cubic_in_out", u);
    ValueId next = mode == sema::TimingMode::Loop
                       ? b.emit(Op::Mod, {b.add(k, b.constF(1.0)), b.constF(count)})
                       : b.min(b.add(k, b.constF(1.0)), b.constF(count - 1.0));
    auto pick = [&](ValueId which, const Vals& values) {
        ValueId v = values.back();
        for (size_t i = values.size() - 1; i-- > 0;)
            v = b.select(b.emit(Op::Eq, {which, b.constF(static_cast<double>(i))}), values[i], v);
        return v;
    };
    auto blend = [&](const Vals& values) { return b.mix(pick(k, values), pick(next, values), w); };

    bool allPhases = true, allWalk = true;
    std::optional<int> first = members[0].family->first;
    for (const BoundFamily& m : members) {
        allPhases &=
            m.family->kind == sema::FamilyKind::Phase && !LayerLowering::walks(layer, m.family);
        allWalk &= LayerLowering::walks(layer, m.family);
        if (m.family->first != first) first.reset();
    }
    if (allPhases) {
        Vals phis;
        for (const BoundFamily& m : members)
            phis.push_back(layers.phaseAt(layer, m, lf, lf.qx, lf.qy));
        return layers.phaseFields(layer, lf, blend(phis), first, enc);
    }
    if (allWalk) {
        FamilyInputs in = layers.inputs(layer, lf, BoundFamily{}, band, enc, wantIndex);
        in.phaseAt = [&](ir::Builder&, ValueId x, ValueId y) {
            Vals radii;
            for (const BoundFamily& m : members)
                radii.push_back(layers.phaseAt(layer, m, lf, x, y));
            return blend(radii);
        };
        Vals sides;
        for (const BoundFamily& m : members) {
            Frame here = layers.frameAt(m, lf, lf.qx, lf.qy);
            sides.push_back(ctx.exprs.scalar(*m.family->facets, here));
        }
        ValueId from = pick(k, sides), to = pick(next, sides);
        // Between two shapes the blend is neither a circle nor a regular polygon, so the
        // solver must take its general scan; its interval needs the blend's least ratio of
        // inradius to radius, which is at least the smaller of the two shapes' cos(pi/N)
        // (a circle counting as infinitely many sides). A side count just below the
        // smaller one gives a slightly smaller ratio and is not whole: the scan, safely.
        auto asSides = [&](ValueId n) {
            return b.select(b.emit(Op::Eq, {n, b.constF(0.0)}), b.constF(1e9), n);
        };
        ValueId fewer = b.sub(b.min(asSides(from), asSides(to)), b.constF(0.5));
        ValueId bothRound = b.emit(
            Op::And, {b.emit(Op::Eq, {from, b.constF(0.0)}), b.emit(Op::Eq, {to, b.constF(0.0)})});
        ValueId between = b.select(bothRound, b.constF(0.0), fewer);
        in.facets = b.select(b.le(w, b.constF(0.0)), from,
                             b.select(b.emit(Op::Ge, {w, b.constF(1.0)}), to, between));
        return familyBuilder(kWalking)(b, in);
    }
    std::vector<LayerFields> fields;
    Vals distances, indices;
    auto sample = std::make_shared<MorphSample>();
    bool sweeps = true;
    for (const BoundFamily& m : members) {
        LayerFields f = layers.familyFields(layer, lf, m, band, enc, wantIndex);
        distances.push_back(f.distance);
        indices.push_back(f.index);
        sample->members.push_back(f.sample);
        sweeps &= f.sample.z != ir::kNoValue;
    }
    b.setLoc(layer.decl->range.begin);
    LayerFields out;
    out.distance = blend(distances);
    out.index = pick(b.select(b.lt(w, b.constF(0.5)), k, next), indices);
    // The views that sweep advance each member in its own parameter and blend the advanced
    // distances as the pattern blends them (Envelope.cpp); a member without a sample (a
    // family given by its distance) leaves the morph without one.
    if (sweeps) {
        sample->from = k;
        sample->to = next;
        sample->weight = w;
        out.sample.z = out.distance;
        out.sample.up = out.sample.down = b.constF(kNoMember);
        out.sample.floor = b.constF(0.0);
        out.sample.morph = std::move(sample);
    }
    return out;
}

} // namespace moire::lower
