#include "compiler/lower/DistanceTubes.h"

#include <span>
#include <vector>

namespace moire::lower {

using ir::Op;
using ir::ValueId;

namespace {

// Probes along a sample's normal after the first (which stands kTubeReach parts' sides out).
// The model lands on the ridge from one probe past it for points, parallel curves and crossing
// lines; the probes are spent getting past the nearest ridge without skipping members (six
// left a grid 1/12 of a pixel apart 5% light, a ray 7% long).
constexpr int kRidgeProbes = 8;
// A ridge is settled where a probe past it puts it within this share of the probe's place.
constexpr double kSettled = 1e-3;
// The first of the probes at this many times the sample's distance (and a fiftieth of a part).
constexpr double kFirstGuess = 3.0;
// The hand-over, by the samples' mean ray length in fine parts' sides (crowded 1 to 0).
constexpr double kCrowdedBelow = 0.7, kPartedAbove = 0.95;
// How the parts see a ray's length, against the tubes: a straight member's (kappa0 M = 0) counts
// kStraightRay times, a point's (kappa0 M large) kPointRay times. The parts read a straight
// member's stroke exactly until a part holds more than two, but a dot's edge only to first
// order, so the dots fail them at half a line's spacing, and lines hold out longer than a
// grid's rows (whose crossings a part reads two strokes of). Straight rays counted once, a
// grid four a pixel read 0.013 off by its tubes where the parts alone were 0.0015 off, and
// rings six a pixel 0.0012 against 0.0001; counted 1.5 times, 0.0015 and 0.0001 (1.4 and 1.6
// left a grid 4.5 to 5 a pixel 0.010 off, or its ink 1.7% light).
constexpr double kStraightRay = 1.5, kPointRay = 0.5;
// The samples read before the tubes may be given up, and the mean ray length (as above) past
// which they are.
constexpr int kFirstSamples = 8;
constexpr double kLongRays = 1.1;
// A probe reads the sample's own member while its foot stands within this share of its step.
constexpr double kSameFoot = 0.5;
// The step along the level set for the curvature, as a share of the sample's distance (at
// least kLeastTurnStep of a part's side).
constexpr double kTurnStep = 0.1, kLeastTurnStep = 0.01;
// Nearer probes for the curvature where those two read other members. A sample taken as on a
// straight member there read its ray's share as h / M for h^2 / M^2, and left dots 1% heavy
// (0.1984 of a share of 0.1963 at four and eight a pixel; 0.1964 with these).
constexpr double kNearerTurnStep = 1.0 / 16;
// The most turn (its tangent: 60 degrees) of a curvature probe's normal over which its foot's
// move is read from the turn (memberCurvature): a chord of the member's circle, 0.58 of the
// move to first order there.
constexpr double kConcaveTurn = 1.732;
// A ray whose member bends towards it ends within this many times its centre of curvature's
// distance (rayThrough): the curvature is read over a step, not at the foot.
constexpr double kFocusMargin = 1.25;

// The next member a ray's probe reads past its ridge runs parallel to the ray's own where
// their normals are within about 25 degrees.
constexpr double kNextParallel = 0.9;

ValueId apart(ir::Builder& b, PixelPoint a, PixelPoint c) {
    return b.hypot(b.sub(a.u, c.u), b.sub(a.v, c.v));
}

// One sample's ray: its foot f, unit normal n (along the pixel's sides), its distance t0 along
// it, in world units.
struct Ray {
    PixelPoint p, f;
    Normal n;
    ValueId t0;
};

// A probe s along the ray: whether it reads the sample's own member (its foot within
// kSameFoot s of the sample's; NaN, a probe on a kink, reads as another's), and the foot and
// unit normal of the member it reads.
struct Probe {
    ValueId same;
    PixelPoint foot;
    Normal n;
};
Probe probeAt(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel, const Ray& ray,
              ValueId s) {
    const PixelPoint q{b.add(ray.f.u, b.mul(s, ray.n.u)), b.add(ray.f.v, b.mul(s, ray.n.v))};
    const Reading r = readThere(b, at, pixel, q);
    const PixelPoint foot = footFrom(b, r, q, false);
    return {b.lt(apart(b, foot, ray.f), b.mul(s, b.constF(kSameFoot))), foot, unitNormal(b, r)};
}

// Where along the ray the sample's member (s away at s) and the member a probe past the ridge
// read are as near, that member taken as bending as the sample's own, kappa >= 0 (a circle of
// radius 1 / kappa through its foot f2, normal n2 there): with a = f - f2,
//     s = (kappa |a|^2 + 2 a . n2) / (2 (1 - n . n2 - kappa a . n)),
// a point's |a|^2 / (-2 a . n) as kappa grows, a line's a . n2 / (1 - n . n2) at 0 (exact for
// a grid's crossing lines, where a point's model only comes down to the ridge from past it).
// -1 where it does not stand ahead along the ray.
ValueId ridgeModel(ir::Builder& b, const Ray& ray, const Probe& past, ValueId kappa) {
    const ValueId au = b.sub(ray.f.u, past.foot.u), av = b.sub(ray.f.v, past.foot.v);
    // A probe past the other member (on it, where evenly spaced members put the model's
    // ridge two spacings on, or beyond) reads the normal of its far side: its near side's,
    // facing back along the ray, is the one the ridge stands on.
    const ValueId beyond =
        b.gt(b.add(b.mul(ray.n.u, past.n.u), b.mul(ray.n.v, past.n.v)), b.constF(0.0));
    const ValueId mu = b.select(beyond, b.neg(past.n.u), past.n.u);
    const ValueId mv = b.select(beyond, b.neg(past.n.v), past.n.v);
    const ValueId alongOther = b.add(b.mul(au, mu), b.mul(av, mv));
    const ValueId alongOwn = b.add(b.mul(au, ray.n.u), b.mul(av, ray.n.v));
    const ValueId facing = b.add(b.mul(ray.n.u, mu), b.mul(ray.n.v, mv));
    const ValueId num =
        b.add(b.mul(kappa, b.add(b.mul(au, au), b.mul(av, av))), b.mul(alongOther, b.constF(2.0)));
    const ValueId den =
        b.mul(b.sub(b.sub(b.constF(1.0), facing), b.mul(kappa, alongOwn)), b.constF(2.0));
    const ValueId s = b.div(num, b.max(den, b.constF(1e-30)));
    const ValueId forward = b.emit(Op::And, {b.gt(den, b.constF(0.0)), b.gt(s, b.constF(0.0))});
    return b.select(forward, b.denan(s, b.constF(-1.0)), b.constF(-1.0));
}

// The ray's length to its ridge, from a probe at `cap` that stands past it: up to
// kRidgeProbes more, each at the model's ridge where it stands inside the bracket the probes
// keep, at its middle where not.
ValueId ridgeAlong(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                   const Ray& ray, const Probe& atCap, ValueId cap, ValueId least, ValueId kappa) {
    const ValueId zero = b.constF(0.0);
    auto within = [&](ValueId est, ValueId lo, ValueId hi) {
        return b.emit(Op::And, {b.emit(Op::Ge, {est, lo}), b.le(est, hi)});
    };
    const ValueId first = ridgeModel(b, ray, atCap, kappa);
    // Carried: the probe, the bracket [lo, hi], the model's ridge (-1: none) and whether it
    // has settled.
    std::vector<ValueId> init{zero, ray.t0, cap,
                              b.select(within(first, ray.t0, cap), first, b.constF(-1.0)), zero};
    auto more = [&](std::span<const ValueId> v) {
        return std::vector<ValueId>{b.emit(
            Op::And, {b.emit(Op::And, {b.lt(v[0], b.constF(kRidgeProbes)), b.lt(v[1], v[2])}),
                      b.lt(v[4], b.constF(0.5))})};
    };
    std::vector<ValueId> out = b.loop(init, more, [&](std::span<const ValueId> v) {
        const ValueId lo = v[1], hi = v[2], est = v[3];
        const ValueId inside = b.emit(Op::And, {b.gt(est, lo), b.lt(est, hi)});
        ValueId s = b.select(inside, est, b.mul(b.add(lo, hi), b.constF(0.5)));
        // The first probe nearer, where the ray most likely ends (a sample stands half-way
        // along a ray of parallel curves on average): from a member k spacings on the model
        // puts the ridge k / 2 spacings out, so from the cap it takes a probe to halve k, and
        // members fifty a pixel stand twenty spacings within it.
        const ValueId guess = b.min(s, b.add(b.mul(ray.t0, b.constF(kFirstGuess)), least));
        s = b.select(b.emit(Op::And, {b.lt(v[0], b.constF(0.5)), b.gt(guess, lo)}), guess, s);
        const Probe probe = probeAt(b, at, pixel, ray, s);
        const ValueId lo2 = b.select(probe.same, s, lo), hi2 = b.select(probe.same, hi, s);
        const ValueId model = ridgeModel(b, ray, probe, kappa);
        const ValueId takes =
            b.emit(Op::And, {b.emit(Op::Not, {probe.same}), within(model, lo2, hi2)});
        const ValueId next = b.select(takes, model, est);
        // Settled where a probe past the ridge puts it where it was probed.
        const ValueId settled =
            b.emit(Op::And, {takes, b.le(b.abs(b.sub(model, s)), b.mul(s, b.constF(kSettled)))});
        return std::vector<ValueId>{b.add(v[0], b.constF(1.0)), lo2, hi2, next,
                                    b.select(settled, b.constF(1.0), v[4])};
    });
    const ValueId lo = out[1], hi = out[2], est = out[3];
    return b.select(within(est, lo, hi), est, b.mul(b.add(lo, hi), b.constF(0.5)));
}

// The curvature kappa0 of the sample's member at its foot, from the level set's through the
// sample: two probes `step` either side along it, each counted where it reads the same member
// (its foot within two steps of the sample's), their normals' turn over the step (tan theta =
// kappa_t step, exact for a circle); kappa0 = kappa_t / (1 - kappa_t t0), the denominator held
// above 1e-4 (a point member's, 0 but for rounding). Where neither probe reads the same member
// (a sample near where three or four members' cells meet, both probes stepping into others'),
// two more probes, kNearerTurnStep as far out.
ValueId memberCurvature(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                        const Ray& ray, ValueId step) {
    const ValueId zero = b.constF(0.0);
    // [the turns' sum, the probes counted, the step]
    auto turns = [&](ValueId by) {
        ValueId turned = zero, counted = zero;
        for (double side : {1.0, -1.0}) {
            const ValueId along = b.mul(by, b.constF(side));
            // The tangent (-n_v, n_u).
            const PixelPoint q{b.sub(ray.p.u, b.mul(along, ray.n.v)),
                               b.add(ray.p.v, b.mul(along, ray.n.u))};
            const Reading r = readThere(b, at, pixel, q);
            const Turn turn = turnOf(b, ray.n, unitNormal(b, r));
            // Along the same member its foot moves by (1 - kappa_t t0), kappa_t = the turn
            // over the step: further than the probe where the level set bends towards the
            // member's centre of curvature (inside a ring, by R / (R - t0)). Counted where it
            // stands within two steps of the sample's foot, or, bending so by under
            // kConcaveTurn, within half the move of it (the inner half of a ring's inside
            // failed two steps: read as on straight members, and rings about a lattice's
            // points 5% light). A crossing member's foot read across a right angle stands
            // nowhere the turn says.
            const ValueId bent = b.mul(turn.tangent, b.constF(side));
            const ValueId moved = b.abs(b.sub(by, b.mul(bent, ray.t0)));
            const ValueId apartBy = apart(b, footFrom(b, r, q, false), ray.f);
            const ValueId concave = b.emit(
                Op::And, {b.lt(bent, zero), b.lt(b.abs(turn.tangent), b.constF(kConcaveTurn))});
            const ValueId near =
                b.emit(Op::Or, {b.lt(apartBy, b.mul(by, b.constF(2.0))),
                                b.emit(Op::And, {concave, b.lt(b.abs(b.sub(apartBy, moved)),
                                                               b.mul(moved, b.constF(0.5)))})});
            const ValueId same = b.emit(Op::And, {near, b.gt(turn.cosine, zero)});
            turned = b.add(turned, b.select(same, bent, zero));
            counted = b.add(counted, b.select(same, b.constF(1.0), zero));
        }
        return std::vector<ValueId>{turned, counted, by};
    };
    std::vector<ValueId> t = turns(step);
    t = b.ifThenElse(
        b.gt(t[1], zero), [&] { return t; },
        [&] { return turns(b.mul(step, b.constF(kNearerTurnStep))); });
    const ValueId turned = t[0], counted = t[1];
    const ValueId kappaT = b.select(
        b.gt(counted, zero), b.div(turned, b.mul(b.max(counted, b.constF(1.0)), t[2])), zero);
    const ValueId below = b.max(b.sub(b.constF(1.0), b.mul(kappaT, ray.t0)), b.constF(1e-4));
    return b.denan(b.div(kappaT, below), zero);
}

// The share of a ray's tube within h of its member: (2h + kappa0 h^2) / (2M + kappa0 M^2), 1
// where h reaches the ridge (kappa0 held above -1 / M: the normals of a member bending towards
// the ray meet past its ridge).
ValueId tubeShare(ir::Builder& b, ValueId h, ValueId ridge, ValueId kappa0) {
    const ValueId k = b.max(kappa0, b.div(b.constF(-0.999), ridge));
    const ValueId inked = b.add(b.mul(h, b.constF(2.0)), b.mul(k, b.mul(h, h)));
    const ValueId whole = b.add(b.mul(ridge, b.constF(2.0)), b.mul(k, b.mul(ridge, ridge)));
    const ValueId share = b.denan(b.div(inked, whole), b.div(h, ridge));
    return b.select(b.lt(h, ridge), b.clamp(share, b.constF(0.0), b.constF(1.0)), b.constF(1.0));
}

} // namespace

RayLength rayThrough(ir::Builder& b, const DistanceAt& at, const PixelFootprint& pixel,
                     const Reading& r, PixelPoint p, ValueId cap, bool next) {
    const ValueId zero = b.constF(0.0);
    const ValueId part = b.div(pixel.size, b.constF(kDistanceFineTaps));
    Ray ray{p, {}, unitNormal(b, r), b.div(r.d, heldLength(b, r))};
    ray.f = {b.sub(p.u, b.mul(ray.t0, ray.n.u)), b.sub(p.v, b.mul(ray.t0, ray.n.v))};
    // A probe at the cap: where it reads the point's own member (or the point stands further
    // out), the ray is longer than the caller needs to know.
    const Probe atCap = probeAt(b, at, pixel, ray, cap);
    const ValueId longer = b.emit(Op::Or, {b.emit(Op::Not, {b.lt(ray.t0, cap)}), atCap.same});
    const std::vector<ValueId> out = b.ifThenElse(
        longer,
        [&] {
            return std::vector<ValueId>{cap, zero};
        },
        [&] {
            const ValueId step =
                b.max(b.mul(ray.t0, b.constF(kTurnStep)), b.mul(part, b.constF(kLeastTurnStep)));
            const ValueId kappa0 = memberCurvature(b, at, pixel, ray, step);
            // A member bending towards the ray (kappa0 < 0) sends its normals through its
            // centre of curvature, 1 / |kappa0| along: no ray of it runs further. Past it a
            // probe may read the member's far side (a ring's, through its centre), whose foot
            // stands 2 / |kappa0| ahead along the ray and reads as the sample's own once the
            // probe is twice that far out: the rays through the centres of rings narrower than
            // their stroke (radius 0.08, stroke 0.2) read their ridge at the next ring's.
            const ValueId focus =
                b.select(b.lt(kappa0, zero),
                         b.div(b.constF(kFocusMargin), b.max(b.neg(kappa0), b.constF(1e-30))), cap);
            const ValueId ridge = ridgeAlong(b, at, pixel, ray, atCap, b.min(cap, focus),
                                             b.mul(part, b.constF(0.02)), b.max(kappa0, zero));
            return std::vector<ValueId>{ridge, kappa0};
        });
    RayLength length{out[0], out[1]};
    if (next) {
        // Half a ray past the ridge the probe reads the next member (a ridge found to within
        // a share of itself leaves it well short of the member after), whose foot stands a
        // spacing along the normal from the ray's own: exact for parallel curves wherever
        // the ridge settled. Where it reads its own member, or the ray ran past the cap,
        // twice the ray.
        const Probe probe = probeAt(b, at, pixel, ray, b.mul(length.ridge, b.constF(1.5)));
        const ValueId apartAlong = b.abs(offsetAlong(b, ray.f, probe.foot, ray.n));
        const ValueId twice = b.mul(length.ridge, b.constF(2.0));
        // A spacing off twice the ridge by more than a quarter is not the next member's.
        const ValueId near = b.lt(b.abs(b.sub(apartAlong, twice)), b.mul(twice, b.constF(0.25)));
        const ValueId read =
            b.emit(Op::And, {b.emit(Op::And, {b.emit(Op::Not, {probe.same}), near}),
                             b.lt(length.ridge, cap)});
        length.next = b.select(read, b.denan(apartAlong, twice), twice);
        const ValueId facing = b.abs(b.add(b.mul(ray.n.u, probe.n.u), b.mul(ray.n.v, probe.n.v)));
        length.across =
            b.emit(Op::And, {b.emit(Op::Not, {probe.same}), b.lt(facing, b.constF(kNextParallel))});
        const ValueId s = b.mul(length.ridge, b.constF(1.5));
        length.acrossAt = {b.add(ray.f.u, b.mul(s, ray.n.u)), b.add(ray.f.v, b.mul(s, ray.n.v))};
    }
    return length;
}

TubeEstimate distanceTubesMean(ir::Builder& b, const DistanceAt& at, ValueId halfWidth,
                               const PixelFootprint& pixel) {
    const ValueId part = b.div(pixel.size, b.constF(kDistanceFineTaps));
    const ValueId cap = b.mul(part, b.constF(kTubeReach));
    const ValueId zero = b.constF(0.0), one = b.constF(1.0);
    // The lattice moved (mod 1) by a shift that runs over the frame's pixels as an R2 sequence
    // does: with the same points in every pixel, a family's rows beat with the lattice's (a
    // grid's lines 1/8 of a pixel apart read 5% light, 8/px in the tests); moved, what is left
    // is a grain of the samples' spread, the same on every backend (a product, a sum and a
    // floor of the pixel's coordinates).
    const PixelPoint shift = pixelShift(b);
    const ValueId shiftU = shift.u, shiftV = shift.v;
    // Carried: the sample, the sums of g and of the (capped) ridges, and the samples read.
    std::vector<ValueId> init{zero, zero, zero, zero};
    // On past the first kFirstSamples while their rays' mean length (as the parts see it)
    // stays short of kLongRays parts' sides: past it the hand-over has not begun (kPartedAbove)
    // and the tubes are not read.
    auto more = [&](std::span<const ValueId> v) {
        const ValueId longRays =
            b.gt(v[2], b.mul(b.mul(part, b.constF(kLongRays)), b.max(v[3], one)));
        const ValueId going =
            b.emit(Op::Or, {b.lt(v[0], b.constF(kFirstSamples)), b.emit(Op::Not, {longRays})});
        return std::vector<ValueId>{b.emit(Op::And, {b.lt(v[0], b.constF(kTubeSamples)), going})};
    };
    std::vector<ValueId> out = b.loop(init, more, [&](std::span<const ValueId> v) {
        // Sample j of a Fibonacci lattice, ((j + 1/2) / N, frac((j G + 1/2) / N)), visited in
        // the order j = i kVisitStep mod N, so that the first few spread across the pixel.
        const ValueId visit = b.div(b.mul(v[0], b.constF(kVisitStep)), b.constF(kTubeSamples));
        const ValueId j = b.round(b.mul(b.sub(visit, b.floor(visit)), b.constF(kTubeSamples)));
        const ValueId across =
            b.div(b.add(b.mul(j, b.constF(kLatticeStep)), b.constF(0.5)), b.constF(kTubeSamples));
        const PixelPoint p{
            b.mul(b.sub(fract(b, b.add(b.div(b.add(j, b.constF(0.5)), b.constF(kTubeSamples)),
                                       shiftU)),
                        b.constF(0.5)),
                  pixel.size),
            b.mul(b.sub(fract(b, b.add(across, shiftV)), b.constF(0.5)), pixel.size)};
        const Reading r = readThere(b, at, pixel, p);
        // A sample on a kink (no gradient) or off the distance's range is not read.
        const ValueId read =
            b.emit(Op::And, {b.gt(r.length, zero), b.emit(Op::Not, {b.lt(r.d, zero)})});
        // The stroke's half-width along the ray, in world units.
        const ValueId h = b.div(halfWidth, heldLength(b, r));
        const RayLength ray = rayThrough(b, at, pixel, r, p, cap);
        const ValueId ridge = ray.ridge;
        const ValueId g = tubeShare(b, h, ridge, ray.kappa0);
        // The ray's length as the parts see it (kStraightRay, kPointRay).
        const ValueId straight = b.div(b.constF(kStraightRay - kPointRay),
                                       b.add(one, b.mul(b.max(ray.kappa0, zero), ridge)));
        const ValueId seen = b.mul(ridge, b.add(b.constF(kPointRay), straight));
        const ValueId counted = b.emit(Op::And, {read, b.emit(Op::Eq, {g, g})});
        return std::vector<ValueId>{b.add(v[0], one), b.add(v[1], b.select(counted, g, zero)),
                                    b.add(v[2], b.select(counted, seen, zero)),
                                    b.add(v[3], b.select(counted, one, zero))};
    });
    const ValueId samples = b.max(out[3], one);
    const ValueId meanRidge = b.div(b.div(out[2], samples), part);
    const ValueId crowded = b.clamp(
        b.div(b.sub(b.constF(kPartedAbove), meanRidge), b.constF(kPartedAbove - kCrowdedBelow)),
        zero, one);
    return {b.div(out[1], samples), b.select(b.gt(out[3], zero), crowded, zero)};
}

} // namespace moire::lower
