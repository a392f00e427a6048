#include "compiler/lower/MorphFamily.h"

#include "compiler/lower/MorphBeat.h"
#include "compiler/lower/Prefilter.h"

#include <functional>
#include <vector>

namespace moire::lower {

using ir::Op;
using ir::ValueId;

namespace {

// The blend D = (1 - w) d1 + w d2 of two families' distances over the square pixel, where their
// members are resolved: the distance form reads D as a distance to a centre line, which it
// is not (D has no zeros where the two families' members part, and kinks along each of them),
// and drew such a morph up to 0.08 RMSE off its exact field half-way through a change. Each
// family's distance is linear in its nearest member's signed distance across the pixel,
// d(x) = |s + n . x| (a line or an edge: n its unit normal, s signed by the index's residual
// where the normal is the index gradient), or for a lattice's dots the length of the offset
// from the dot's centre, |s n + x|; the pixel's ink is the share of kBlendSamples^2 points
// where D < h, each a ramp of one sample's width. kNoValue where a family's normal is not
// known (a walking family's, or none).
constexpr int kBlendSamples = 6;
ValueId sampledBlend(ir::Builder& b, const std::vector<LayerFields>& fields, ValueId w,
                     ValueId half, const PixelFootprint& pixel,
                     const std::function<ValueId(ValueId, const Vals&)>& pick, ValueId k,
                     ValueId next) {
    auto c = [&](double v) { return b.constF(v); };
    // Each family's distance as the least of up to kForms lines' (a lattice's edges are its
    // two or three strands, CrowdEstimate::strands, where it draws them), each a signed
    // distance s and unit normal (nu, nv) in pixel units; unused forms repeat the first.
    constexpr size_t kForms = 3;
    std::vector<Vals> s(kForms), nu(kForms), nv(kForms);
    Vals dots;
    for (const LayerFields& f : fields) {
        MemberNormal n = memberNormal(b, f.distance, f.gradX, f.gradY, pixel);
        if (n.u == ir::kNoValue) return ir::kNoValue;
        ValueId length = b.max(b.hypot(n.u, n.v), c(1e-30));
        ValueId across = b.div(f.distance, pixel.size);
        if (!n.ofDistance) {
            ValueId index = f.smooth != ir::kNoValue ? f.smooth : f.index;
            ValueId residual = b.sub(index, b.floor(b.add(index, c(0.5))));
            across = b.select(b.lt(residual, c(0.0)), b.neg(across), across);
        }
        struct Form {
            ValueId s, nu, nv;
        };
        std::vector<Form> forms{{across, b.div(n.u, length), b.div(n.v, length)}};
        if (f.crowd.strandsOn != ir::kNoValue && f.crowd.strands.size() <= kForms) {
            // A strand's nearest line: its residual over its gradient, along the gradient.
            std::vector<Form> lines;
            for (const Footprint& st : f.crowd.strands) {
                PixelSides g = onPixelSides(b, st.gradX, st.gradY, pixel);
                ValueId glen = b.max(b.hypot(g.u, g.v), c(1e-30));
                ValueId residual = b.sub(st.index, b.floor(b.add(st.index, c(0.5))));
                lines.push_back(
                    {b.div(residual, b.mul(glen, pixel.size)), b.div(g.u, glen), b.div(g.v, glen)});
            }
            // Where the lattice draws its points, its own distance's form in every slot.
            const Form base = forms.front();
            const ValueId on = f.crowd.strandsOn;
            forms.clear();
            for (const Form& l : lines)
                forms.push_back({b.select(on, l.s, base.s), b.select(on, l.nu, base.nu),
                                 b.select(on, l.nv, base.nv)});
        }
        while (forms.size() < kForms) forms.push_back(forms.front());
        for (size_t q = 0; q < kForms; ++q) {
            s[q].push_back(forms[q].s);
            nu[q].push_back(forms[q].nu);
            nv[q].push_back(forms[q].nv);
        }
        dots.push_back(f.sample.lattice ? f.sample.lattice->dots
                                        : b.emit(ir::Op::Eq, {c(1.0), c(0.0)}));
    }
    struct Member {
        std::vector<ValueId> s, nu, nv;
        ValueId dots;
    };
    auto member = [&](ValueId which) {
        Member m;
        for (size_t q = 0; q < kForms; ++q) {
            m.s.push_back(pick(which, s[q]));
            m.nu.push_back(pick(which, nu[q]));
            m.nv.push_back(pick(which, nv[q]));
        }
        m.dots = pick(which, dots);
        return m;
    };
    const Member from = member(k), to = member(next);
    const ValueId h = b.div(half, pixel.size);
    auto distanceAt = [&](const Member& m, ValueId ou, ValueId ov) {
        ValueId line = c(1e30);
        for (size_t q = 0; q < kForms; ++q)
            line = b.min(line, b.abs(b.add(m.s[q], b.add(b.mul(m.nu[q], ou), b.mul(m.nv[q], ov)))));
        ValueId dot = b.hypot(b.add(b.mul(m.s[0], m.nu[0]), ou), b.add(b.mul(m.s[0], m.nv[0]), ov));
        return b.select(m.dots, dot, line);
    };
    ValueId sum = c(0.0);
    for (int i = 0; i < kBlendSamples; ++i)
        for (int j = 0; j < kBlendSamples; ++j) {
            ValueId ou = c((i + 0.5) / kBlendSamples - 0.5),
                    ov = c((j + 0.5) / kBlendSamples - 0.5);
            ValueId d = b.mix(distanceAt(from, ou, ov), distanceAt(to, ou, ov), w);
            sum = b.add(
                sum, b.clamp(b.add(b.mul(b.sub(h, d), c(kBlendSamples)), c(0.5)), c(0.0), c(1.0)));
        }
    return b.denan(b.mul(sum, c(1.0 / (kBlendSamples * kBlendSamples))), c(0.0));
}

// Under the mean filter a morph across kinds draws its blended distance from its nearest
// member alone (the distance form), too light where the members crowd. There the blend is
// D = a d1 + b d2 (a = 1 - w, b = w) of two families' distances that run independently across
// the pixel, each distributed as its family's share of the plane within a distance
// (CrowdEstimate::share; a phase family's is 2 h |grad f|), and the pixel's ink is the chance
// that D < h. Split where the line a d1 + b d2 = h crosses d1 = h / 2a, d2 = h / 2b (a pixel
// cannot be past both), it is
//   P(D < h) = int_0^{h/2a} F2((h - a x) / b) dF1(x) + int_0^{h/2b} F1((h - b y) / a) dF2(y)
//              - F1(h / 2a) F2(h / 2b),
// each integral in kMorphTaps steps of its own family's share, and each integrand the other
// family's share over a range of distance no longer than h / 2 of the blend. Read in one
// integral over the family of the larger weight, a near-finished change put its last step's
// integrand over the other family's whole range of distance and drew 1.2% of ink too much
// (a grid to a triangle lattice 99% of the way). The steps' ends grow as the square of
// their count, so that where a family's weight is small (its range long: h / 2b) the first
// steps hold its distances, whose integrand is read at the step's lower end in the first and
// at its middle beyond: exact at either end of a change, where it is one family's own share.
// Handed over to by members per pixel (kCrowdFrom to kCrowdFull), a family's own
// where it has an index gradient, else by the layer's spacing, mixed as the morph mixes the
// families: where members are resolved the blend's strokes travel from one shape to the
// other, and `nearest` samples them over the pixel (sampledBlend). Unset where a family gives
// no share (a walking family, one given by its distance): the distance form then draws the
// blend.
constexpr int kMorphTaps = 8;
CrowdEstimate blendedCrowd(SceneContext& ctx, const sema::CheckedLayer& layer,
                           const StrokeBand& band, const std::vector<LayerFields>& fields,
                           ValueId distance, ValueId k, ValueId next, ValueId w,
                           const std::function<ValueId(ValueId, const Vals&)>& pick) {
    ir::Builder& b = ctx.b;
    auto c = [&](double v) { return b.constF(v); };
    const ValueId pixelSize = b.div(band.a, c(kAntialiasPixels));
    const ValueId spacing = b.abs(ctx.layerProp(layer, "spacing")[0]);
    const ValueId half = b.max(b.mul(ctx.layerProp(layer, "stroke")[0], c(0.5)), c(0.0));
    using Share = std::function<ValueId(ir::Builder&, ValueId)>;
    std::vector<Share> shares;
    Vals crowded;
    for (const LayerFields& f : fields) {
        ValueId members;
        if (f.footprint.grad != ir::kNoValue) {
            ValueId grad = f.footprint.grad;
            shares.push_back([grad](ir::Builder& bb, ValueId h) {
                return bb.min(bb.mul(bb.mul(bb.max(h, bb.constF(0.0)), bb.constF(2.0)), grad),
                              bb.constF(1.0));
            });
            members = b.mul(grad, pixelSize);
        } else if (f.crowd.share) {
            shares.push_back(f.crowd.share);
            members = b.div(pixelSize, b.max(spacing, c(1e-9)));
        } else {
            return {};
        }
        crowded.push_back(b.smoothstep(c(kCrowdFrom), c(kCrowdFull), members));
    }
    // The share of each family at a half-width, for the pair the change runs between: every
    // family's evaluated and picked by k and next.
    auto shareOf = [&](ValueId which, ValueId h) {
        Vals at;
        for (const Share& sh : shares) at.push_back(sh(b, h));
        return pick(which, at);
    };
    // int_0^{h/2 own} F_other((h - own x) / weight) dF_which(x), and F_which at its end.
    auto halfIntegral = [&](ValueId which, ValueId other, ValueId own, ValueId weight) {
        const ValueId top = b.div(half, b.mul(b.max(own, c(1e-6)), c(2.0)));
        const ValueId apart = b.max(weight, c(1e-6));
        ValueId sum = c(0.0), below = shareOf(which, c(0.0));
        for (int t = 1; t <= kMorphTaps; ++t) {
            const double n2 = double(kMorphTaps) * kMorphTaps;
            const ValueId at = shareOf(which, b.mul(top, c(t * t / n2)));
            const ValueId mid =
                b.mul(top, c(t == 1 ? 0.0 : ((t - 1) * (t - 1) + t * t) / (2 * n2)));
            sum = b.add(sum, b.mul(b.sub(at, below),
                                   shareOf(other, b.div(b.sub(half, b.mul(own, mid)), apart))));
            below = at;
        }
        return std::pair{sum, below};
    };
    CrowdEstimate out;
    out.engaged = b.mix(pick(k, crowded), pick(next, crowded), w);
    const PixelFootprint pixel{pixelSize, ctx.cosTurn, ctx.sinTurn};
    // Each form behind a branch: the crowded where the hand-over takes any of it, the sampled
    // where it leaves any.
    out.mean = b.ifThenElse(
        b.gt(out.engaged, c(0.0)),
        [&] {
            const auto [one, oneEnd] = halfIntegral(k, next, b.sub(c(1.0), w), w);
            const auto [two, twoEnd] = halfIntegral(next, k, w, b.sub(c(1.0), w));
            ValueId mean = b.sub(b.add(one, two), b.mul(oneEnd, twoEnd));
            // Where a line of one family runs along a line of the other, their beat.
            mean = morphBeat(b, fields, k, next, w, half, pixel, pick, mean);
            // At either end of a change the morph is one family, whose own mean over the
            // pixel (layerMeanInk) is exact where its crowded share is the plane's average:
            // each family's difference from its share enters with its weight in the blend.
            Vals own;
            for (size_t i = 0; i < fields.size(); ++i)
                own.push_back(b.sub(layerMeanInk(b, fields[i], half, pixel), shares[i](b, half)));
            mean = b.add(mean, b.mix(pick(k, own), pick(next, own), w));
            return Vals{b.clamp(b.denan(mean, c(0.0)), c(0.0), c(1.0))};
        },
        [&] { return Vals{c(0.0)}; })[0];
    out.nearest = b.ifThenElse(
        b.lt(out.engaged, c(1.0)),
        [&] {
            ValueId v = sampledBlend(
                b, fields, w, half, pixel,
                [&](ValueId which, const Vals& vals) { return pick(which, vals); }, k, next);
            if (v == ir::kNoValue)
                v = distanceInk(b, distance, half, ir::kNoValue, ir::kNoValue, pixel);
            return Vals{v};
        },
        [&] { return Vals{c(0.0)}; })[0];
    return out;
}

} // namespace

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
    auto pick = [&](ValueId which, const Vals& values) { return b.pick(which, values); };
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
        LayerFields out = layers.phaseFields(layer, lf, blend(phis), first, enc);
        layers.readWhereBent(out, layer, lf, band, first, enc, [&](ValueId x, ValueId y) {
            Vals there;
            for (const BoundFamily& m : members)
                there.push_back(layers.phaseAt(layer, m, lf, x, y));
            return blend(there);
        });
        return out;
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
        fields.push_back(f);
        distances.push_back(f.distance);
        indices.push_back(f.index);
        sample->members.push_back(f.sample);
        sweeps &= f.sample.z != ir::kNoValue;
    }
    b.setLoc(layer.decl->range.begin);
    LayerFields out;
    out.distance = blend(distances);
    if (ctx.options.filter == sema::FilterMode::Mean)
        out.crowd = blendedCrowd(ctx, layer, band, fields, out.distance, k, next, w, pick);
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
