#include "compiler/lower/LowerScene.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Builder.h"
#include "compiler/ir/Semantics.h"
#include "compiler/lower/LatticeFamily.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/LowerExpr.h"
#include "compiler/lower/Timings.h"
#include "compiler/lower/WalkingFamily.h"

#include <numbers>
#include <set>
#include <tuple>

namespace moire::lower {

using namespace ast;
using ir::Op;
using ir::ValueId;

namespace {

class SceneLowering {
  public:
    SceneLowering(const sema::CheckedScene& scene, ir::Function& f, const LowerOptions& options)
        : scene_(scene), options_(options), b_(f), exprs_(b_), timings_(b_, exprs_, scene) {
        exprs_.setTimings([this](const Decl* timing) { return timings_.progress(timing); });
    }

    void run(OutputLayout& layout) {
        // Frame settings.
        Vals size =
            settingOr(scene_.scene, "size", {b_.constF(kDefaultWidth), b_.constF(kDefaultHeight)});
        b_.output(layout.numKernelOutputs + OutputLayout::kSettingWidth, size[0]);
        b_.output(layout.numKernelOutputs + OutputLayout::kSettingHeight, size[1]);

        // Camera: world = center + Rot(rotation) (pixel - image centre) / zoom, with y up.
        Vals center = settingOr(scene_.camera, "center", {b_.constF(0.0), b_.constF(0.0)});
        if (options_.probeSlot >= 0)
            center = {b_.param(options_.probeSlot), b_.param(options_.probeSlot + 1)};
        ValueId zoom = settingOr(scene_.camera, "zoom", {b_.constF(1.0)})[0];
        const Expr* turn = scene_.camera && scene_.camera->prop("rotation")
                               ? scene_.camera->prop("rotation")->value.get()
                               : nullptr;
        const int settings = layout.numKernelOutputs;
        b_.output(settings + OutputLayout::kSettingZoom, zoom);
        b_.output(settings + OutputLayout::kSettingCenterX, center[0]);
        b_.output(settings + OutputLayout::kSettingCenterY, center[1]);
        b_.output(settings + OutputLayout::kSettingTurn,
                  turn ? exprs_.scalar(*turn, constantFrame_) : b_.constF(0.0));
        const bool view = options_.viewSlot >= 0;
        if (view) {
            center = {b_.add(center[0], viewParam(ViewSlots::kPanX)),
                      b_.add(center[1], viewParam(ViewSlots::kPanY))};
            zoom = b_.mul(zoom, viewParam(ViewSlots::kZoomFactor));
        }
        b_.setLoc({});
        ValueId sx = b_.sub(b_.leaf(Op::PixelX), b_.mul(b_.leaf(Op::ImageW), b_.constF(0.5)));
        ValueId sy = b_.sub(b_.mul(b_.leaf(Op::ImageH), b_.constF(0.5)), b_.leaf(Op::PixelY));
        // The world size of one pixel. The scene's `size` frames the picture; rendering at
        // another size shows the same frame at that resolution (fitted if the aspect
        // differs), so a print-size render is the same picture with more pixels.
        ValueId fit = b_.constF(1.0);
        if (options_.probeSlot < 0)
            fit =
                b_.max(b_.div(size[0], b_.leaf(Op::ImageW)), b_.div(size[1], b_.leaf(Op::ImageH)));
        ValueId pixel = b_.div(fit, zoom);
        auto [rx, ry] =
            turn ? rotate(sx, sy, exprs_.scalar(*turn, constantFrame_)) : std::pair{sx, sy};
        // Everything downstream is differentiated with respect to these two values.
        ValueId wx = b_.mul(rx, pixel), wy = b_.mul(ry, pixel);
        // The default centre is the origin; adding 0 would cost two ops per pixel.
        if (view || options_.probeSlot >= 0 || (scene_.camera && scene_.camera->prop("center"))) {
            wx = b_.add(center[0], wx);
            wy = b_.add(center[1], wy);
        }
        world_.x = b_.emit(Op::Indep, {wx}, 0.0, 0);
        world_.y = b_.emit(Op::Indep, {wy}, 0.0, 1);

        Vals bg = settingOr(scene_.scene, "background",
                            {b_.constF(1), b_.constF(1), b_.constF(1), b_.constF(1)});
        Ink acc = paper(b_, bg[0], bg[1], bg[2], bg[3]);
        const ValueId zero = b_.constF(0.0);
        ValueId unresolved = zero; // the largest gain s |grad f| of the encoded layers

        for (size_t i = 0; i < scene_.layers.size(); ++i) {
            const sema::CheckedLayer& layer = scene_.layers[i];
            Vals color =
                prop(layer, "color", {b_.constF(0), b_.constF(0), b_.constF(0), b_.constF(1)});
            ValueId stroke = prop(layer, "stroke", {b_.constF(1.0)})[0];
            ValueId opacity = prop(layer, "opacity", {b_.constF(1.0)})[0];
            checkValues(layer);
            b_.setLoc(layer.decl->range.begin);
            StrokeBand band = strokeBand(b_, stroke, pixel);
            Encoding enc = encoding(layer);
            LayerFields fields = layerFields(layer, band, enc, layout.layerFields);
            if (enc.field != ir::kNoValue) unresolved = b_.max(unresolved, sampling(layer, enc));
            b_.setLoc(layer.decl->range.begin);
            ValueId cov = strokeCoverage(b_, fields.distance, band, opacity, color[3]);
            acc = inkOver(b_, acc, color[0], color[1], color[2], cov);
            if (layout.layerFields) {
                b_.output(layout.indexSlot(static_cast<int>(i)), fields.index);
                b_.output(layout.distanceSlot(static_cast<int>(i)), fields.distance);
                auto orZero = [&](ValueId v) { return v == ir::kNoValue ? b_.constF(0.0) : v; };
                b_.output(layout.gradXSlot(static_cast<int>(i)), orZero(fields.gradX));
                b_.output(layout.gradYSlot(static_cast<int>(i)), orZero(fields.gradY));
                b_.output(layout.aux0Slot(static_cast<int>(i)), orZero(fields.aux0));
                b_.output(layout.aux1Slot(static_cast<int>(i)), orZero(fields.aux1));
            }
        }
        // The sampling limit (§10.4): a carrier of pitch s cannot show fringes much finer than
        // 3 s, so where an encoded field is that steep the scene's `unresolved` tint is laid
        // over everything (transparent unless the scene sets it).
        if (unresolved != zero) {
            Vals tint = settingOr(scene_.scene, "unresolved", {zero, zero, zero, zero});
            ValueId mark = b_.smoothstep(b_.constF(0.30), b_.constF(0.37), unresolved);
            acc = inkOver(b_, acc, tint[0], tint[1], tint[2],
                          b_.mul(mark, b_.clamp(tint[3], zero, b_.constF(1.0))));
        }
        Ink out = unpremultiply(b_, acc);
        b_.output(0, out.r);
        b_.output(1, out.g);
        b_.output(2, out.b);
        b_.output(3, out.a);
        // The timings used, for clips (loop lengths) and for the frame's checks.
        timings_.outputSettings(layout, layout.numKernelOutputs + OutputLayout::kNumSettings);
        // The values the frame checks before drawing them (ValueCheck).
        for (auto& [value, check] : checks_) {
            b_.output(layout.numKernelOutputs + layout.numSettings(), value);
            layout.checks.push_back(std::move(check));
        }
        b_.function().numOutputs = layout.numKernelOutputs + layout.numSettings();
    }

  private:
    ValueId viewParam(int slot) { return b_.param(options_.viewSlot + slot); }

    // Records `e` (each component of a vector) for the frame to check against `rule`.
    void check(const Expr& e, ValueCheck::Rule rule, const std::string& name) {
        // A morph gives one property to every family with that parameter: checked once.
        if (!checked_.insert({&e, rule}).second) return;
        Vals v = exprs_.lower(e, world_);
        for (size_t i = 0; i < v.size(); ++i) {
            // A component of a vector written out is located by itself.
            const bool written = e.kind == ExprKind::Vector && e.args.size() == v.size();
            const Expr& at = written ? *e.args[i] : e;
            checks_.push_back(
                {v[i], ValueCheck{rule, "'" + name + "'", at.range, e.type == Type::Angle, false}});
        }
    }
    // A layer's values that the float renderers could not draw (docs/language.md, "Limits").
    void checkValues(const sema::CheckedLayer& layer) {
        using R = ValueCheck::Rule;
        static const std::pair<const char*, R> rules[] = {
            {"spacing", R::Spacing},  {"phase", R::Finite},  {"stroke", R::Positive},
            {"opacity", R::Unit},     {"origin", R::Finite}, {"rotation", R::Finite},
            {"offset", R::Finite},    {"turn", R::Finite},   {"gain", R::Finite},
            {"morph_time", R::Finite}};
        for (const auto& [name, rule] : rules)
            if (const Expr* e = layer.prop(name)) check(*e, rule, name);
        std::vector<const sema::CheckedLayer::Member*> members;
        sema::CheckedLayer::Member single{layer.family, layer.args};
        if (layer.morph.empty() && layer.family) members.push_back(&single);
        for (const sema::CheckedLayer::Member& m : layer.morph) members.push_back(&m);
        for (const sema::CheckedLayer::Member* m : members) {
            const Decl& fam = *m->family->decl;
            for (size_t i = 0; i < fam.params.size(); ++i) {
                if (!m->args[i] || fam.params[i].type == Type::Color) continue;
                check(*m->args[i], R::Finite, fam.params[i].name);
            }
            // A polygon family's side count, when a parameter gives it (ngon's `sides`): a
            // fraction or fewer than 3 is no polygon (its phase would not close up).
            const Expr* facets = m->family->facets;
            if (facets && facets->kind == ExprKind::Name && facets->ref == RefKind::FamilyParam) {
                const int p = facets->refIndex;
                const Expr* value = m->args[p] ? m->args[p] : fam.params[p].defaultValue.get();
                if (value) check(*value, R::Sides, fam.params[p].name);
            }
        }
    }

    std::pair<ValueId, ValueId> rotate(ValueId x, ValueId y, ValueId angle) {
        ValueId c = b_.cos(angle), s = b_.sin(angle);
        return {b_.sub(b_.mul(c, x), b_.mul(s, y)), b_.add(b_.mul(s, x), b_.mul(c, y))};
    }

    Vals settingOr(const Decl* block, const char* name, Vals fallback) {
        if (!block) return fallback;
        const Property* p = block->prop(name);
        if (!p) return fallback;
        return exprs_.lower(*p->value, constantFrame_);
    }

    Vals prop(const sema::CheckedLayer& layer, const char* name, Vals fallback) {
        const Expr* e = layer.prop(name);
        return e ? exprs_.lower(*e, world_) : fallback;
    }

    // A field encoded into a layer (§10.1): the phase becomes phi - gain s f.
    struct Encoding {
        ValueId field = ir::kNoValue, gain = ir::kNoValue;
    };
    Encoding encoding(const sema::CheckedLayer& layer) {
        Encoding enc;
        if (!layer.encoded) return enc;
        enc.field = prop(layer, "field", {})[0];
        enc.gain = prop(layer, "gain", {b_.constF(1.0)})[0];
        return enc;
    }
    // gain s |grad f|, whose reciprocal is the fringe spacing in carrier pitches: the
    // fringes are legible while it stays under about 1/3 (c / |grad f| >= 3 s, Eq. 38).
    ValueId sampling(const sema::CheckedLayer& layer, const Encoding& enc) {
        ValueId spacing = prop(layer, "spacing", {b_.constF(10.0)})[0];
        ValueId slope =
            b_.hypot(b_.emit(Op::DerivX, {enc.field}), b_.emit(Op::DerivY, {enc.field}));
        return b_.mul(b_.abs(b_.mul(enc.gain, spacing)), slope);
    }

    // Where a layer's family is evaluated: its own frame, q = Rot(-rotation) (p - origin).
    struct LayerFrame {
        ValueId qx, qy; // the point in the layer's frame
        ValueId dx, dy; // p - origin, in world axes
        ValueId spacing, phase;
    };

    // The fields of one layer: its family's, or a morph's blend of its families'.
    LayerFields layerFields(const sema::CheckedLayer& layer, const StrokeBand& band,
                            const Encoding& enc, bool wantIndex) {
        b_.setLoc(layer.decl->range.begin);
        LayerFrame lf;
        lf.spacing = prop(layer, "spacing", {b_.constF(10.0)})[0];
        lf.phase = prop(layer, "phase", {b_.constF(0.0)})[0];
        Vals origin = prop(layer, "origin", {b_.constF(0.0), b_.constF(0.0)});
        const Expr* turn = layer.prop("rotation");
        ValueId px = world_.x, py = world_.y;
        if (options_.viewSlot >= 0) {
            // The viewer's rigid motion M(p) = Rot(a) p + d carries the layer: evaluate it at
            // M^-1(p) = Rot(-a) (p - d).
            const int i = static_cast<int>(&layer - scene_.layers.data());
            std::tie(px, py) =
                rotate(b_.sub(px, viewParam(ViewSlots::layer(i, ViewSlots::kLayerDx))),
                       b_.sub(py, viewParam(ViewSlots::layer(i, ViewSlots::kLayerDy))),
                       b_.neg(viewParam(ViewSlots::layer(i, ViewSlots::kLayerTurn))));
        }
        lf.dx = b_.sub(px, origin[0]);
        lf.dy = b_.sub(py, origin[1]);
        std::tie(lf.qx, lf.qy) = turn ? rotate(lf.dx, lf.dy, b_.neg(exprs_.scalar(*turn, world_)))
                                      : std::pair{lf.dx, lf.dy};
        if (layer.morph.empty())
            return familyFields(layer, lf, bind(layer.family, layer.args), band, enc, wantIndex);
        return morphFields(layer, lf, band, enc, wantIndex);
    }

    // One family with a layer's arguments lowered, ready to be evaluated at any point of the
    // layer's frame. Null for a layer that writes its phase itself.
    struct BoundFamily {
        const sema::CheckedFamily* family = nullptr;
        std::vector<Vals> params;
    };
    BoundFamily bind(const sema::CheckedFamily* family, const std::vector<const Expr*>& args) {
        BoundFamily bf{family, {}};
        if (!family) return bf;
        const Decl& fam = *family->decl;
        for (size_t i = 0; i < fam.params.size(); ++i) {
            const Expr* value = args[i] ? args[i] : fam.params[i].defaultValue.get();
            MOIRE_CHECK(value, "missing family argument survived checking");
            bf.params.push_back(exprs_.lower(*value, world_));
        }
        return bf;
    }
    // The family's expressions at a point of its frame: a fresh frame with the layer's
    // arguments, its lets lowered anew (they may use x and y).
    Frame frameAt(const BoundFamily& bf, const LayerFrame& lf, ValueId x, ValueId y) {
        Frame f;
        f.x = x;
        f.y = y;
        f.spacing = lf.spacing;
        f.family = bf.family ? bf.family->decl : nullptr;
        f.params = bf.params;
        if (bf.family)
            for (const Let& l : bf.family->decl->lets) f.lets.push_back(exprs_.lower(*l.value, f));
        return f;
    }
    ValueId phaseAt(const sema::CheckedLayer& layer, const BoundFamily& bf, const LayerFrame& lf,
                    ValueId x, ValueId y) {
        const Expr* phase = bf.family ? bf.family->phase : layer.anonymousPhase;
        MOIRE_CHECK(phase, "layer without a phase survived checking");
        Frame f = frameAt(bf, lf, x, y);
        return exprs_.scalar(*phase, f);
    }
    // Whether the layer draws this family by the walking solver (walking applies to the
    // families that can walk; in a morph, the others ignore it).
    static bool walks(const sema::CheckedLayer& layer, const sema::CheckedFamily* family) {
        return layer.walking && family && family->facets;
    }

    // The fields of one family in the layer's frame, by the kind of family.
    LayerFields familyFields(const sema::CheckedLayer& layer, const LayerFrame& lf,
                             const BoundFamily& bf, const StrokeBand& band, const Encoding& enc,
                             bool wantIndex) {
        b_.setLoc(layer.decl->range.begin);
        const sema::CheckedFamily* family = bf.family;
        if (family && family->kind == sema::FamilyKind::Builtin) {
            LatticeInputs in{lf.qx, lf.qy, lf.spacing, bf.params.at(0), bf.params.at(1)[0]};
            return latticeFields(b_, latticeKind(family->decl->name), in);
        }
        if (family && family->kind == sema::FamilyKind::Distance) {
            Frame here = frameAt(bf, lf, lf.qx, lf.qy);
            LayerFields out;
            out.distance = exprs_.scalar(*family->distance, here);
            out.index = family->index ? exprs_.scalar(*family->index, here) : b_.constF(0.0);
            return out;
        }
        if (walks(layer, family)) {
            Frame here = frameAt(bf, lf, lf.qx, lf.qy);
            ValueId facets = exprs_.scalar(*family->facets, here);
            RadiusFn rho = [&](ir::Builder&, ValueId x, ValueId y) {
                return phaseAt(layer, bf, lf, x, y);
            };
            return walkingFields(layer, lf, rho, facets, band, enc, wantIndex);
        }
        ValueId phi = phaseAt(layer, bf, lf, lf.qx, lf.qy);
        std::optional<int> first = family ? family->first : std::nullopt;
        ValueId near = ir::kNoValue;
        if (first && enc.field == ir::kNoValue) {
            // The phase a millionth of the radius away, off any fold through the centre (the
            // direction is along no line a family would fold on): ample for float, whose
            // resolution there is about 6e-8 of the radius, and the gradient it gives moves
            // by about a millionth.
            ValueId e = b_.mul(b_.hypot(lf.qx, lf.qy), b_.constF(1e-6));
            near = phaseAt(layer, bf, lf, b_.add(lf.qx, e),
                           b_.add(lf.qy, b_.mul(e, b_.constF(0.6180339887))));
        }
        return phaseFields(layer, lf, phi, first, enc, near);
    }

    // A phase family (Eq. 5), with the encoded field subtracted first (§10.1): forward-mode
    // AD gives the gradient of the whole phase, field included.
    LayerFields phaseFields(const sema::CheckedLayer& layer, const LayerFrame& lf, ValueId phi,
                            std::optional<int> first, const Encoding& enc,
                            ValueId near = ir::kNoValue) {
        b_.setLoc(layer.decl->range.begin);
        if (enc.field != ir::kNoValue)
            phi = b_.sub(phi, b_.mul(b_.mul(enc.gain, lf.spacing), enc.field));
        return phaseFamilyFields(b_, phi, lf.phase, lf.spacing, first, near);
    }

    // A walking family (§6-7) of radius rho, by the certified search.
    LayerFields walkingFields(const sema::CheckedLayer& layer, const LayerFrame& lf,
                              const RadiusFn& rho, ValueId facets, const StrokeBand& band,
                              const Encoding& enc, bool wantIndex) {
        WalkingInputs in;
        in.px = lf.qx;
        in.py = lf.qy;
        in.spacing = lf.spacing;
        in.phase = lf.phase;
        // Encoding shifts every member's residual by -gain s f(p): the same as moving the
        // phase by +gain s f. The residual is then divided by the carrier gradient, taken as
        // radial from the layer's origin (a first-order convenience, §10.1), minus
        // gain s grad f; the solver works in residual units, so its stroke band is scaled by
        // that length and its distance divided by it.
        ValueId slope = ir::kNoValue;
        if (enc.field != ir::kNoValue) {
            ValueId shift = b_.mul(b_.mul(enc.gain, lf.spacing), enc.field);
            in.phase = b_.add(lf.phase, shift);
            ValueId rr = b_.max(b_.hypot(lf.dx, lf.dy), b_.constF(ir::kTiny));
            ValueId gx = b_.sub(b_.div(lf.dx, rr), b_.emit(Op::DerivX, {shift}));
            ValueId gy = b_.sub(b_.div(lf.dy, rr), b_.emit(Op::DerivY, {shift}));
            slope = b_.max(b_.hypot(gx, gy), b_.constF(ir::kTiny));
        }
        Vals offset = prop(layer, "offset", {b_.constF(0.0), b_.constF(0.0)});
        in.offsetX = offset[0];
        in.offsetY = offset[1];
        // Member n is turned by n * turn with n whole, so a turn is the same taken modulo a full
        // turn; reduced to (-pi, pi] here (per frame, in double, when it does not depend on
        // the pixel) so that n * turn stays small enough for the float renderers to resolve.
        ValueId turn = prop(layer, "turn", {b_.constF(0.0)})[0];
        ValueId turns = b_.round(b_.div(turn, b_.constF(2.0 * std::numbers::pi)));
        ValueId reduced = b_.sub(turn, b_.mul(turns, b_.constF(2.0 * std::numbers::pi)));
        in.turn = b_.select(b_.le(b_.abs(turn), b_.constF(std::numbers::pi)), turn, reduced);
        in.facets = facets;
        in.band = band;
        if (slope != ir::kNoValue) in.band = {b_.mul(band.h, slope), b_.mul(band.a, slope)};
        in.wantIndex = wantIndex;
        in.tally = options_.tally;
        LayerFields out = walkingFamilyFields(b_, in, rho);
        if (slope != ir::kNoValue) out.distance = b_.div(out.distance, slope);
        return out;
    }

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
    // back to interpolating the two distances.
    LayerFields morphFields(const sema::CheckedLayer& layer, const LayerFrame& lf,
                            const StrokeBand& band, const Encoding& enc, bool wantIndex) {
        std::vector<BoundFamily> members;
        for (const sema::CheckedLayer::Member& m : layer.morph)
            members.push_back(bind(m.family, m.args));
        b_.setLoc(layer.decl->range.begin);
        const double count = static_cast<double>(members.size());
        const sema::TimingMode mode = scene_.timings.at(layer.morphTiming).mode;
        ValueId raw = timings_.progress(layer.morphTiming).raw;
        ValueId along = b_.mul(raw, b_.constF(count));
        ValueId k = b_.min(b_.floor(along), b_.constF(count - 1.0));
        ValueId share = b_.div(timings_.period(layer.morphTiming), b_.constF(count));
        ValueId seconds = b_.mul(b_.sub(along, k), share);
        // A change longer than a share would still be under way when the next one starts.
        ValueId length =
            b_.clamp(prop(layer, "morph_time", {b_.constF(0.28)})[0], b_.constF(1e-6), share);
        ValueId u = b_.clamp(b_.div(b_.sub(seconds, b_.sub(share, length)), length), b_.constF(0.0),
                             b_.constF(1.0));
        ValueId w = timings_.ease("cubic_in_out", u);
        ValueId next = mode == sema::TimingMode::Loop
                           ? b_.emit(Op::Mod, {b_.add(k, b_.constF(1.0)), b_.constF(count)})
                           : b_.min(b_.add(k, b_.constF(1.0)), b_.constF(count - 1.0));
        auto pick = [&](ValueId which, const Vals& values) {
            ValueId v = values.back();
            for (size_t i = values.size() - 1; i-- > 0;)
                v = b_.select(b_.emit(Op::Eq, {which, b_.constF(static_cast<double>(i))}),
                              values[i], v);
            return v;
        };
        auto blend = [&](const Vals& values) {
            return b_.mix(pick(k, values), pick(next, values), w);
        };

        bool allPhases = true, allWalk = true;
        std::optional<int> first = members[0].family->first;
        for (const BoundFamily& m : members) {
            allPhases &= m.family->kind == sema::FamilyKind::Phase && !walks(layer, m.family);
            allWalk &= walks(layer, m.family);
            if (m.family->first != first) first.reset();
        }
        if (allPhases) {
            Vals phis;
            for (const BoundFamily& m : members)
                phis.push_back(phaseAt(layer, m, lf, lf.qx, lf.qy));
            return phaseFields(layer, lf, blend(phis), first, enc);
        }
        if (allWalk) {
            RadiusFn rho = [&](ir::Builder&, ValueId x, ValueId y) {
                Vals radii;
                for (const BoundFamily& m : members) radii.push_back(phaseAt(layer, m, lf, x, y));
                return blend(radii);
            };
            Vals sides;
            for (const BoundFamily& m : members) {
                Frame here = frameAt(m, lf, lf.qx, lf.qy);
                sides.push_back(exprs_.scalar(*m.family->facets, here));
            }
            ValueId from = pick(k, sides), to = pick(next, sides);
            // Between two shapes the blend is neither a circle nor a regular polygon, so the
            // solver must take its general scan; its interval needs the blend's least ratio of
            // inradius to radius, which is at least the smaller of the two shapes' cos(pi/N)
            // (a circle counting as infinitely many sides). A side count just below the
            // smaller one gives a slightly smaller ratio and is not whole: the scan, safely.
            auto asSides = [&](ValueId n) {
                return b_.select(b_.emit(Op::Eq, {n, b_.constF(0.0)}), b_.constF(1e9), n);
            };
            ValueId fewer = b_.sub(b_.min(asSides(from), asSides(to)), b_.constF(0.5));
            ValueId bothRound = b_.emit(Op::And, {b_.emit(Op::Eq, {from, b_.constF(0.0)}),
                                                  b_.emit(Op::Eq, {to, b_.constF(0.0)})});
            ValueId between = b_.select(bothRound, b_.constF(0.0), fewer);
            ValueId facets =
                b_.select(b_.le(w, b_.constF(0.0)), from,
                          b_.select(b_.emit(Op::Ge, {w, b_.constF(1.0)}), to, between));
            return walkingFields(layer, lf, rho, facets, band, enc, wantIndex);
        }
        std::vector<LayerFields> fields;
        Vals distances, indices;
        for (const BoundFamily& m : members) {
            LayerFields f = familyFields(layer, lf, m, band, enc, wantIndex);
            distances.push_back(f.distance);
            indices.push_back(f.index);
        }
        b_.setLoc(layer.decl->range.begin);
        LayerFields out;
        out.distance = blend(distances);
        out.index = pick(b_.select(b_.lt(w, b_.constF(0.5)), k, next), indices);
        return out;
    }

    const sema::CheckedScene& scene_;
    const LowerOptions& options_;
    ir::Builder b_;
    ExprLowering exprs_;
    TimingLowering timings_;
    Frame world_;
    Frame constantFrame_; // scene settings cannot use x or y (checked)
    std::vector<std::pair<ValueId, ValueCheck>> checks_;
    std::set<std::pair<const Expr*, ValueCheck::Rule>> checked_;
};

} // namespace

ir::Function lowerScene(const sema::CheckedScene& scene, const LowerOptions& options,
                        OutputLayout& layout) {
    layout.numLayers = static_cast<int>(scene.layers.size());
    layout.layerFields = options.layerFields;
    layout.numKernelOutputs =
        4 + (options.layerFields ? OutputLayout::kFieldsPerLayer * layout.numLayers : 0);
    ir::Function f;
    f.name = "scene";
    SceneLowering(scene, f, options).run(layout);
    ir::verify(f);
    return f;
}

} // namespace moire::lower
