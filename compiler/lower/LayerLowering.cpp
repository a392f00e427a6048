#include "compiler/lower/LayerLowering.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/BuiltValue.h"
#include "compiler/ir/Plane.h"
#include "compiler/lower/DistanceFamily.h"
#include "compiler/lower/MorphFamily.h"

namespace moire::lower {

using namespace ast;
using ir::BuiltValue;
using ir::Op;
using ir::ValueId;

Encoding LayerLowering::encoding(const sema::CheckedLayer& layer) {
    Encoding enc;
    if (!layer.encoded) return enc;
    enc.field = ctx_.layerProp(layer, "field")[0];
    enc.gain = ctx_.layerProp(layer, "gain")[0];
    return enc;
}

// The fringes are legible while gain s |grad f| stays under about 1/3 (c / |grad f| >= 3 s,
// Eq. 38).
ValueId LayerLowering::sampling(const sema::CheckedLayer& layer, const Encoding& enc) {
    ir::Builder& b = ctx_.b;
    ValueId spacing = ctx_.layerProp(layer, "spacing")[0];
    ValueId slope = b.hypot(b.emit(Op::DerivX, {enc.field}), b.emit(Op::DerivY, {enc.field}));
    return b.mul(b.abs(b.mul(enc.gain, spacing)), slope);
}

LayerFields LayerLowering::fields(const sema::CheckedLayer& layer, const StrokeBand& band,
                                  const Encoding& enc, bool wantIndex) {
    ir::Builder& b = ctx_.b;
    b.setLoc(layer.decl->range.begin);
    auto built = [&](ValueId v) { return BuiltValue(b, v); };
    LayerFrame lf;
    lf.spacing = ctx_.layerProp(layer, "spacing")[0];
    lf.phase = ctx_.layerProp(layer, "phase")[0];
    Vals origin = ctx_.layerProp(layer, "origin");
    const Expr* turn = layer.prop("rotation");
    ir::Vec2T<BuiltValue> p{built(ctx_.world.x), built(ctx_.world.y)};
    auto turnBy = [&](ValueId angle) {
        lf.turn = lf.turn == ir::kNoValue ? angle : b.add(lf.turn, angle);
    };
    if (ctx_.interactive()) {
        // The viewer's rigid motion M(p) = Rot(a) p + d carries the layer: evaluate it at
        // M^-1(p) = Rot(-a) (p - d).
        const int i = static_cast<int>(&layer - ctx_.scene.layers.data());
        ir::Vec2T<BuiltValue> moved{
            p.x - built(ctx_.viewParam(ViewSlots::layer(i, ViewSlots::kLayerDx))),
            p.y - built(ctx_.viewParam(ViewSlots::layer(i, ViewSlots::kLayerDy)))};
        const ValueId viewTurn = ctx_.viewParam(ViewSlots::layer(i, ViewSlots::kLayerTurn));
        p = ir::rotate(moved, -built(viewTurn));
        turnBy(viewTurn);
    }
    ir::Vec2T<BuiltValue> d{p.x - built(origin[0]), p.y - built(origin[1])};
    lf.dx = d.x.id;
    lf.dy = d.y.id;
    ir::Vec2T<BuiltValue> q = d;
    if (turn) {
        const ValueId angle = ctx_.exprs.scalar(*turn, ctx_.world);
        q = ir::rotate(d, -built(angle));
        turnBy(angle);
    }
    lf.qx = q.x.id;
    lf.qy = q.y.id;
    if (layer.morph.empty())
        return familyFields(layer, lf, bind(layer.family, layer.args), band, enc, wantIndex);
    return morphFields(*this, layer, lf, band, enc, wantIndex);
}

BoundFamily LayerLowering::bind(const sema::CheckedFamily* family,
                                const std::vector<const Expr*>& args) {
    BoundFamily bf{family, {}};
    if (!family) return bf;
    const Decl& fam = *family->decl;
    for (size_t i = 0; i < fam.params.size(); ++i) {
        const Expr* value = args[i] ? args[i] : fam.params[i].defaultValue.get();
        MOIRE_CHECK(value, "missing family argument survived checking");
        bf.params.push_back(ctx_.exprs.lower(*value, ctx_.world));
    }
    return bf;
}

// A fresh frame with the layer's arguments, its lets lowered anew (they may use x and y).
Frame LayerLowering::frameAt(const BoundFamily& bf, const LayerFrame& lf, ValueId x, ValueId y) {
    Frame f;
    f.x = x;
    f.y = y;
    f.spacing = lf.spacing;
    f.family = bf.family ? bf.family->decl : nullptr;
    f.params = bf.params;
    if (bf.family)
        for (const Let& l : bf.family->decl->lets) f.lets.push_back(ctx_.exprs.lower(*l.value, f));
    return f;
}

ValueId LayerLowering::phaseAt(const sema::CheckedLayer& layer, const BoundFamily& bf,
                               const LayerFrame& lf, ValueId x, ValueId y) {
    const Expr* phase = bf.family ? bf.family->phase : layer.anonymousPhase;
    MOIRE_CHECK(phase, "layer without a phase survived checking");
    Frame f = frameAt(bf, lf, x, y);
    return ctx_.exprs.scalar(*phase, f);
}

// Walking applies to the families that can walk; in a morph, the others ignore it.
bool LayerLowering::walks(const sema::CheckedLayer& layer, const sema::CheckedFamily* family) {
    return layer.walking && family && family->facets;
}

FamilyInputs LayerLowering::inputs(const sema::CheckedLayer& layer, const LayerFrame& lf,
                                   const BoundFamily& bf, const StrokeBand& band,
                                   const Encoding& enc, bool wantIndex) {
    FamilyInputs in;
    in.at = lf;
    in.params = bf.params;
    in.band = band;
    in.enc = enc;
    in.wantIndex = wantIndex;
    in.tally = ctx_.options.tally;
    in.walking = ctx_.options.walking;
    in.sweeps = ctx_.options.view && sema::viewSweeps(*ctx_.options.view);
    in.crowd = ctx_.options.filter == sema::FilterMode::Mean;
    in.cosTurn = ctx_.cosTurn;
    in.sinTurn = ctx_.sinTurn;
    in.layerProp = [this, &layer](std::string_view name) { return ctx_.layerProp(layer, name); };
    return in;
}

// The fields of one family in the layer's frame, by the kind of family.
LayerFields LayerLowering::familyFields(const sema::CheckedLayer& layer, const LayerFrame& lf,
                                        const BoundFamily& bf, const StrokeBand& band,
                                        const Encoding& enc, bool wantIndex) {
    ir::Builder& b = ctx_.b;
    b.setLoc(layer.decl->range.begin);
    const sema::CheckedFamily* family = bf.family;
    if (family && family->kind == sema::FamilyKind::Builtin)
        return familyBuilder(family->decl->name)(b, inputs(layer, lf, bf, band, enc, wantIndex));
    if (family && family->kind == sema::FamilyKind::Distance) {
        Frame here = frameAt(bf, lf, lf.qx, lf.qy);
        LayerFields out;
        out.distance = ctx_.exprs.scalar(*family->distance, here);
        out.index = family->index ? ctx_.exprs.scalar(*family->index, here) : b.constF(0.0);
        if (ctx_.options.filter == sema::FilterMode::Mean) {
            // The distance about the pixel (DistanceFamily.h): the family's expression at the
            // pixel's point moved by a world offset.
            auto at = [&](ir::Builder& bb, ValueId ox, ValueId oy) {
                const auto [x, y] = movedBy(bb, lf, ox, oy);
                Frame there = frameAt(bf, lf, x, y);
                return ctx_.exprs.scalar(*family->distance, there);
            };
            const PixelFootprint pixel = pixelOf(band);
            out.crowd = distanceFamilyCrowd(
                b, out.distance, at, b.mul(ctx_.layerProp(layer, "stroke")[0], b.constF(0.5)),
                pixel);
        }
        return out;
    }
    if (walks(layer, family)) {
        Frame here = frameAt(bf, lf, lf.qx, lf.qy);
        FamilyInputs in = inputs(layer, lf, bf, band, enc, wantIndex);
        in.facets = ctx_.exprs.scalar(*family->facets, here);
        in.phaseAt = [&](ir::Builder&, ValueId x, ValueId y) {
            return phaseAt(layer, bf, lf, x, y);
        };
        return familyBuilder(kWalking)(b, in);
    }
    ValueId phi = phaseAt(layer, bf, lf, lf.qx, lf.qy);
    std::optional<int> first = family ? family->first : std::nullopt;
    ValueId near = ir::kNoValue;
    if (first) {
        const auto [x, y] = offFold(b, lf.qx, lf.qy);
        near = phaseAt(layer, bf, lf, x, y);
    }
    LayerFields out = phaseFields(layer, lf, phi, first, enc, near);
    readWhereBent(out, layer, lf, band, first, enc,
                  [&](ValueId x, ValueId y) { return phaseAt(layer, bf, lf, x, y); });
    return out;
}

void LayerLowering::readWhereBent(LayerFields& fields, const sema::CheckedLayer& layer,
                                  const LayerFrame& lf, const StrokeBand& band,
                                  std::optional<int> first, const Encoding& enc,
                                  const PhaseAtPoint& phiAt) {
    // A family with a first member is read in parts its own way, below the first member as
    // well (readBelowFirst).
    if (ctx_.options.filter != sema::FilterMode::Mean) return;
    ir::Builder& b = ctx_.b;
    const ValueId halfWidth = b.mul(ctx_.layerProp(layer, "stroke")[0], b.constF(0.5));
    // The members' level at the pixel's point moved by the world offset (ox, oy): moved by a
    // field the layer encodes, read there too (as phaseFields moves it at the pixel's point).
    auto level = [&](ir::Builder& bb, ValueId ox, ValueId oy) {
        if (enc.field == ir::kNoValue) return lf.phase;
        return levelOf(bb, lf, enc, fieldAt(layer, ox, oy));
    };
    auto at = [&](ir::Builder& bb, ValueId ox, ValueId oy) {
        const auto [x, y] = movedBy(bb, lf, ox, oy);
        return indexOfPhase(bb, phiAt(x, y), level(bb, ox, oy), lf.spacing);
    };
    if (first) {
        // Each part's phase, the phase off a fold through it (offFold) as familyFields reads
        // the pixel's, and the members' level there.
        auto phases = [&](ir::Builder& bb, ValueId ox, ValueId oy) {
            const auto [x, y] = movedBy(bb, lf, ox, oy);
            const auto [nx, ny] = offFold(bb, x, y);
            return PartPhase{phiAt(x, y), phiAt(nx, ny), level(bb, ox, oy)};
        };
        return readBelowFirst(fields, lf, band, halfWidth, *first, phases, at);
    }
    const BentIndex bent = bentIndexMean(b, at, fields.footprint, halfWidth, pixelOf(band));
    fields.footprint.bent = bent.weight;
    fields.footprint.bentMean = bent.mean;
}

void LayerLowering::readBelowFirst(LayerFields& fields, const LayerFrame& lf,
                                   const StrokeBand& band, ValueId halfWidth, int first,
                                   const PhasesAt& phases, const IndexAt& indexAt) {
    ir::Builder& b = ctx_.b;
    const PixelFootprint pixel = pixelOf(band);
    // Each part's P = (phi / s)^2, read off a fold for its gradient, and the first member's
    // phi in spacings: l + first with the members' level l = level / s, or where the level
    // puts members at or below the fold (phi < 0, which no point reaches), the first above it,
    // l + floor(-l) + 1.
    auto at = [&](ir::Builder& bb, ValueId ox, ValueId oy) {
        const PartPhase part = phases(bb, ox, oy);
        auto spacings = [&](ValueId phi) {
            return indexOfPhase(bb, phi, bb.constF(0.0), lf.spacing);
        };
        auto squared = [&](ValueId phi) {
            const ValueId v = spacings(phi);
            return bb.mul(v, v);
        };
        const ValueId l = spacings(part.level);
        const ValueId lead =
            bb.max(bb.add(l, bb.constF(double(first))),
                   bb.add(bb.add(l, bb.floor(bb.sub(bb.constF(0.0), l))), bb.constF(1.0)));
        return FoldAt{squared(part.phi), squared(part.near), l, lead};
    };
    const Bend bend = bendOf(b, indexAt, fields.footprint, pixel);
    const ValueId below = reachesBelowFirst(b, fields.footprint, pixel);
    const ValueId read = b.emit(ir::Op::Or, {below, b.gt(bend.weight, b.constF(0.0))});
    // Read in P, in the parts P's own bend asks for, at least 2 x 2 (4 x 4 where the fold
    // crosses the pixel): each part's cells are taken at four midpoints across it, and one
    // part a pixel left 0.002 to 0.004 RMSE along the asymptotes where 4 x 4 leave 0.001.
    const ValueId parts = b.ifThenElse(
        read,
        [&] {
            const ValueId least = b.select(below, b.constF(4.0), b.constF(2.0));
            const ValueId n = foldParts(b, at, indexAt, pixel, least);
            return std::vector<ValueId>{belowFirstMean(b, at, halfWidth, pixel, n)};
        },
        [&] { return std::vector<ValueId>{b.constF(0.0)}; })[0];
    fields.footprint.bent = bend.weight;
    fields.footprint.bentMean = parts;
    fields.footprint.belowMean = parts;
}

// The point a millionth of the radius from (x, y), off any fold through it (the direction is
// along no line a family would fold on): ample for float, whose resolution there is about 6e-8
// of the radius, and the gradient read there moves by about a millionth.
std::pair<ValueId, ValueId> LayerLowering::offFold(ir::Builder& b, ValueId x, ValueId y) {
    ValueId e = b.mul(b.hypot(x, y), b.constF(1e-6));
    return {b.add(x, e), b.add(y, b.mul(e, b.constF(0.6180339887)))};
}

// The layer's encoded field at the pixel's world point moved by (ox, oy): its expression
// lowered again in a frame of its own, so that nothing lowered at the pixel's point is reused.
ValueId LayerLowering::fieldAt(const sema::CheckedLayer& layer, ValueId ox, ValueId oy) {
    ir::Builder& b = ctx_.b;
    Frame there;
    there.x = b.add(ctx_.world.x, ox);
    there.y = b.add(ctx_.world.y, oy);
    return ctx_.exprs.property(layer.decl, sema::layerProperties(), "field", there)[0];
}

// The layer's frame's point for the pixel's point moved by the world offset (ox, oy): the
// offset turned into the layer's frame.
std::pair<ValueId, ValueId> LayerLowering::movedBy(ir::Builder& b, const LayerFrame& lf, ValueId ox,
                                                   ValueId oy) {
    ir::Vec2T<BuiltValue> o{BuiltValue(b, ox), BuiltValue(b, oy)};
    if (lf.turn != ir::kNoValue) o = ir::rotate(o, -BuiltValue(b, lf.turn));
    return {b.add(lf.qx, o.x.id), b.add(lf.qy, o.y.id)};
}

// The pixel as the mean filter's readings in parts see it: its side in world units (the
// antialias band's over its width in pixels) and the camera's turn.
PixelFootprint LayerLowering::pixelOf(const StrokeBand& band) {
    ir::Builder& b = ctx_.b;
    return {b.div(band.a, b.constF(kAntialiasPixels)), ctx_.cosTurn, ctx_.sinTurn};
}

// A phase family (Eq. 5), its members moved by the field it encodes (§10.1): member n is where
// phi - gain s f = n s + phase, so the field moves the members' level to phase + gain s f and
// the family's own phase stays as it is, which a first member's reading needs (it takes phi as
// the square root of a smooth function: subtracted from phi, the field drew the member the
// hyperbola leaves out as a hairline along its asymptotes). Forward-mode AD gives the index's
// gradient, field included.
LayerFields LayerLowering::phaseFields(const sema::CheckedLayer& layer, const LayerFrame& lf,
                                       ValueId phi, std::optional<int> first, const Encoding& enc,
                                       ValueId near) {
    ir::Builder& b = ctx_.b;
    b.setLoc(layer.decl->range.begin);
    const ValueId level = enc.field == ir::kNoValue ? lf.phase : levelOf(b, lf, enc, enc.field);
    return phaseFamilyFields(b, phi, level, lf.spacing, first, near);
}

// The members' level where a layer encodes `field` (its value at some point): phase + gain s f.
ValueId LayerLowering::levelOf(ir::Builder& b, const LayerFrame& lf, const Encoding& enc,
                               ValueId field) {
    return b.add(lf.phase, b.mul(b.mul(enc.gain, lf.spacing), field));
}

} // namespace moire::lower
