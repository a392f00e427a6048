#include "runtime/Clip.h"

#include "compiler/Compile.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>
#include <vector>

namespace moire::clip {

namespace {

using i128 = __int128;

i128 gcd128(i128 a, i128 b) {
    if (a < 0) a = -a;
    if (b < 0) b = -b;
    while (b != 0) {
        i128 r = a % b;
        a = b;
        b = r;
    }
    return a;
}

// num / den reduced, or nullopt when it does not fit 64 bits.
std::optional<Rational> reduce(i128 num, i128 den) {
    if (den == 0) return std::nullopt;
    if (den < 0) num = -num, den = -den;
    i128 g = gcd128(num, den);
    if (g > 1) num /= g, den /= g;
    constexpr i128 kMax = std::numeric_limits<int64_t>::max();
    if (num > kMax || num < -kMax || den > kMax) return std::nullopt;
    return Rational{static_cast<int64_t>(num), static_cast<int64_t>(den)};
}

i128 abs128(i128 v) {
    return v < 0 ? -v : v;
}

std::string describeRational(Rational r) {
    if (r.den == 1) return fmt::format("{}", r.num);
    return fmt::format("{}/{}", r.num, r.den);
}

} // namespace

Rational approximate(double v, int64_t maxDen) {
    if (!std::isfinite(v) || maxDen < 1) return {};
    const bool negative = v < 0;
    const double x = std::fabs(v);
    // Below 2^-60 the nearest fraction with a small denominator is 0 anyway; stopping there
    // keeps x's exact binary fraction p / 2^k within 128 bits.
    if (x < std::ldexp(1.0, -60)) return {};
    // x = p / q exactly: a 53-bit mantissa over a power of two (or an integer).
    int exp = 0;
    const double mant = std::frexp(x, &exp); // x = mant * 2^exp, mant in [0.5, 1)
    i128 p = static_cast<i128>(std::ldexp(mant, 53));
    i128 q = 1;
    if (exp >= 53)
        p <<= (exp - 53);
    else
        q <<= (53 - exp);
    // Euclid on p / q gives the continued fraction [a0; a1, ...]; h / k are its convergents.
    i128 h0 = 0, h1 = 1, k0 = 1, k1 = 0;
    i128 num = p, den = q;
    while (den != 0) {
        i128 a = num / den;
        i128 h2 = a * h1 + h0, k2 = a * k1 + k0;
        if (k2 > maxDen) {
            // The best fraction with a bounded denominator is the last convergent or the
            // largest semiconvergent under the bound, whichever is nearer.
            i128 m = (maxDen - k0) / k1;
            i128 hs = m * h1 + h0, ks = m * k1 + k0;
            // |p/q - hs/ks| < |p/q - h1/k1|  <=>  |p ks - hs q| k1 < |p k1 - h1 q| ks
            if (m > 0 && abs128(p * ks - hs * q) * k1 < abs128(p * k1 - h1 * q) * ks)
                h1 = hs, k1 = ks;
            break;
        }
        h0 = h1, h1 = h2, k0 = k1, k1 = k2;
        i128 r = num - a * den;
        num = den;
        den = r;
    }
    Rational out = reduce(h1, k1).value_or(Rational{});
    if (negative) out.num = -out.num;
    return out;
}

std::optional<Rational> add(Rational a, Rational b) {
    return reduce(static_cast<i128>(a.num) * b.den + static_cast<i128>(b.num) * a.den,
                  static_cast<i128>(a.den) * b.den);
}

std::optional<Rational> lcm(Rational a, Rational b) {
    if (a.num <= 0 || b.num <= 0) return std::nullopt;
    // For fractions in lowest terms, the common multiples of p1/q1 and p2/q2 are the
    // multiples of lcm(p1, p2) / gcd(q1, q2).
    i128 g = gcd128(a.num, b.num);
    i128 num = static_cast<i128>(a.num) / g * b.num;
    return reduce(num, std::gcd(a.den, b.den));
}

bool readsClock(const SceneProgram& program) {
    struct Walk {
        bool found = false;
        // With a stack of its own: a long chain of sums is as deep as it is long.
        void expr(const ast::Expr* root) {
            std::vector<const ast::Expr*> todo{root};
            while (!todo.empty() && !found) {
                const ast::Expr* e = todo.back();
                todo.pop_back();
                if (!e) continue;
                if (e->kind == ast::ExprKind::Name && e->ref == ast::RefKind::Builtin &&
                    e->name == "t")
                    found = true;
                for (const ast::ExprPtr& a : e->args) todo.push_back(a.get());
            }
        }
    } walk;
    for (const auto& module : program.modules)
        for (const ast::DeclPtr& d : module->decls) {
            for (const ast::FamilyParam& p : d->params) walk.expr(p.defaultValue.get());
            for (const ast::Let& l : d->lets) walk.expr(l.value.get());
            for (const ast::Property& p : d->props) walk.expr(p.value.get());
            walk.expr(d->value.get());
        }
    return walk.found;
}

bool movesWithClock(const SceneProgram& program) {
    for (const ir::Function* f : {&program.frame, &program.kernel})
        for (const ir::Block& b : f->blocks)
            for (const ir::Inst& inst : b.insts)
                if (inst.op == ir::Op::Time) return true;
    return false;
}

namespace {

// A timing's cycle as a fraction: the period and delay are each read as the nearest fraction
// with a bounded denominator, then added exactly.
std::optional<Rational> cycleOf(const TimingValues& t) {
    Rational period = approximate(t.period);
    // A period under half a millisecond rounds to 0 at kMaxDenominator: read it finer.
    if (period.num == 0) period = approximate(t.period, int64_t{1} << 40);
    std::optional<Rational> c = approximate(t.delay);
    for (int i = 0; i < (t.mode == TimingValues::PingPong ? 2 : 1) && c; ++i) c = add(*c, period);
    return c;
}

std::string describeTiming(const TimingValues& t) {
    std::string s = fmt::format("{} {}", t.name, describeSeconds(t.cycle()));
    if (t.mode == TimingValues::PingPong)
        s += t.delay != 0 ? fmt::format(" (pingpong: {:g} s + 2 x {:g} s)", t.delay, t.period)
                          : fmt::format(" (pingpong: 2 x {:g} s)", t.period);
    else if (t.delay != 0)
        s += fmt::format(" ({:g} s + {:g} s delay)", t.period, t.delay);
    return s;
}

} // namespace

Length defaultLength(const Motion& motion, double t0, double fps) {
    Length out;
    std::vector<const TimingValues*> loopers, running; // running: once timings not yet at rest
    double restAt = t0;
    for (const TimingValues& t : motion.timings) {
        if (t.mode != TimingValues::Once) {
            loopers.push_back(&t);
        } else if (t.cycle() > t0) {
            running.push_back(&t);
            restAt = std::max(restAt, t.cycle());
        }
    }
    if (loopers.empty() && running.empty()) {
        if (motion.moves && (motion.readsClock || motion.timings.empty())) {
            out.error = "the scene reads the clock t directly and has no timing to say when it "
                        "repeats, so the clip has no natural length; give --to or --frames";
            return out;
        }
        out.still = true;
        out.notes.push_back(motion.timings.empty()
                                ? "the scene does not move: writing one frame"
                                : fmt::format("the scene does not move from t = {:g} on (its "
                                              "timings have come to rest): writing one frame",
                                              t0));
        return out;
    }

    int64_t frames = 0;
    bool capped = false;
    if (!loopers.empty()) {
        std::optional<Rational> loop;
        std::string cycles;
        for (const TimingValues* t : loopers) {
            std::optional<Rational> c = cycleOf(*t);
            if (!c || c->num <= 0) {
                out.error = fmt::format("timing '{}' has a cycle (delay + period) of {:g} s, so "
                                        "it never repeats; give --to or --frames",
                                        t->name, t->cycle());
                return out;
            }
            loop = loop ? lcm(*loop, *c) : c;
            cycles += (cycles.empty() ? "" : ", ") + describeTiming(*t);
            if (!loop || loop->value() > kMaxLoopSeconds) {
                capped = true;
                break;
            }
        }
        if (capped) {
            frames = std::max<int64_t>(1, std::llround(kMaxLoopSeconds * fps));
            out.notes.push_back(fmt::format(
                "the timings' cycles ({}) close together only after {}, more than the {} a clip "
                "may run by default: writing the first {} ({} frames), which will not loop; give "
                "--to or --frames for another length",
                cycles, loop ? describeSeconds(loop->value()) : std::string("an age"),
                describeSeconds(kMaxLoopSeconds), describeSeconds(kMaxLoopSeconds), frames));
        } else {
            out.loop = *loop;
            // Frames per loop: exact when fps is itself a fraction with a small denominator
            // (24, 29.97, 30000 / 1001); otherwise within a billionth of a whole number.
            Rational f = approximate(fps, 1001);
            double perLoop = out.loop.value() * fps;
            bool whole = std::fabs(perLoop - std::round(perLoop)) <= 1e-9 * perLoop;
            if (std::fabs(f.value() - fps) <= 1e-12 * fps) {
                std::optional<Rational> n = reduce(static_cast<i128>(out.loop.num) * f.num,
                                                   static_cast<i128>(out.loop.den) * f.den);
                if (n) whole = n->den == 1;
            }
            frames = std::max<int64_t>(1, std::llround(perLoop));
            const std::string head = fmt::format(
                "the loop is {}{}, the least common multiple of the timings' cycles ({})",
                describeSeconds(out.loop.value()),
                out.loop.den == 1 ? "" : fmt::format(" ({} s)", describeRational(out.loop)),
                cycles);
            if (whole) {
                out.seamless = true;
                out.notes.push_back(fmt::format("{}: {} frames at {:g} fps", head, frames, fps));
            } else {
                // Whole-number rates that loop exactly are the multiples of the loop's
                // denominator: offer the nearest ones.
                std::string better;
                const int64_t q = out.loop.den;
                if (q <= 240) {
                    int64_t below = static_cast<int64_t>(fps / q) * q, above = below + q;
                    better = below > 0 ? fmt::format("; at {} or {} fps it would", below, above)
                                       : fmt::format("; at {} fps it would", above);
                }
                out.notes.push_back(fmt::format(
                    "{}, which is {:.6g} frames at {:g} fps: writing {}, so the clip will not "
                    "join exactly{}",
                    head, perLoop, fps, frames, better));
            }
        }
    }

    if (!running.empty()) {
        std::string names;
        for (const TimingValues* t : running)
            names += (names.empty() ? "'" : ", '") + t->name + "'";
        // The first frame at or after the moment the last once-timing comes to rest.
        const int64_t needed = framesBefore(t0, restAt, fps) + 1;
        if (!loopers.empty() && !capped) {
            const int64_t loops = (needed + frames - 1) / frames;
            frames *= loops;
            out.notes.push_back(fmt::format(
                "{} {} run{} once, at rest from t = {:g}: the clip runs {} loop{} to cover {}, "
                "but starts before {} {} done, so it will not join seamlessly (--from {:g} "
                "starts after and loops)",
                running.size() == 1 ? "timing" : "timings", names, running.size() == 1 ? "s" : "",
                restAt, loops, loops == 1 ? "" : "s", running.size() == 1 ? "it" : "them",
                running.size() == 1 ? "it" : "they", running.size() == 1 ? "is" : "are", restAt));
        } else if (loopers.empty()) {
            frames = needed;
            out.notes.push_back(fmt::format(
                "the scene's motion runs once ({}) and comes to rest at t = {:g}: {} frames, "
                "the last at rest; the clip does not loop",
                names, restAt, frames));
        }
        out.seamless = false;
        if (static_cast<double>(frames) > kMaxLoopSeconds * fps) {
            frames = std::max<int64_t>(1, std::llround(kMaxLoopSeconds * fps));
            out.notes.push_back(fmt::format("that is more than the {} a clip may run by default: "
                                            "writing the first {} frames; give --to or --frames "
                                            "for another length",
                                            describeSeconds(kMaxLoopSeconds), frames));
        }
    }

    if (motion.readsClock) {
        out.seamless = false;
        out.notes.push_back("the scene also reads the clock t directly, which no timing's cycle "
                            "bounds, so the clip may not join at its end");
    }

    // What reading each cycle as a fraction costs the join: how far the loop length, measured
    // in the cycle as written, lies from a whole number of cycles.
    if (out.seamless) {
        for (const TimingValues* t : loopers) {
            double cycles = out.loop.value() / t->cycle();
            double off = cycles - std::round(cycles);
            if (std::fabs(off) >= 1e-6)
                out.notes.push_back(fmt::format(
                    "timing '{}' has a cycle of {:.10g} s, read as {} s: the clip ends {:.2g}% of "
                    "that cycle from a whole number of them (write the period as a fraction, "
                    "like 1 / 3, to close the loop exactly)",
                    t->name, t->cycle(), describeRational(*cycleOf(*t)), std::fabs(off) * 100));
        }
    }
    out.frames = frames;
    return out;
}

std::optional<FrameRange> parseFrames(const std::string& text, std::string& error) {
    // Frame numbers stay far below 2^53, where n / fps would stop being exact.
    constexpr int64_t kMaxFrame = 999'999'999'999;
    auto number = [](std::string_view s, int64_t& v) {
        auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        return ec == std::errc() && end == s.data() + s.size() && !s.empty() && v >= 0 &&
               v <= kMaxFrame;
    };
    std::string_view s = text;
    FrameRange r;
    size_t dots = s.find("..");
    bool ok;
    if (dots == std::string_view::npos) {
        int64_t n = 0;
        ok = number(s, n) && n >= 1;
        r = {0, n - 1};
    } else {
        ok = number(s.substr(0, dots), r.first) && number(s.substr(dots + 2), r.last) &&
             r.first <= r.last;
    }
    if (!ok) {
        error = fmt::format("--frames must be a count N (frames 0 to N-1) or a range A..B of "
                            "frame numbers (A <= B, both included, at most {}), not '{}'",
                            kMaxFrame, text);
        return std::nullopt;
    }
    return r;
}

int64_t framesBefore(double t0, double t1, double fps) {
    double x = (t1 - t0) * fps;
    if (!(x > 0)) return 0;
    double nearest = std::round(x);
    if (std::fabs(x - nearest) <= 1e-6 * std::max(1.0, x)) return static_cast<int64_t>(nearest);
    return static_cast<int64_t>(std::ceil(x));
}

std::string NamePattern::name(int64_t frame) const {
    if (!numbered) return before;
    return before +
           (zeroPad ? fmt::format("{:0{}d}", frame, width) : fmt::format("{:{}d}", frame, width)) +
           after;
}

std::optional<NamePattern> parseNamePattern(const std::string& path, std::string& error) {
    NamePattern p;
    // Only the file name is a pattern: a '%' in a directory is part of its name.
    size_t slash = path.rfind('/');
    size_t start = slash == std::string::npos ? 0 : slash + 1;
    p.before = path.substr(0, start);
    std::string* part = &p.before;
    for (size_t i = start; i < path.size(); ++i) {
        if (path[i] != '%') {
            *part += path[i];
            continue;
        }
        size_t j = i + 1;
        if (j < path.size() && path[j] == '%') {
            *part += '%';
            i = j;
            continue;
        }
        bool zero = j < path.size() && path[j] == '0';
        if (zero) ++j;
        int width = 0;
        while (j < path.size() && std::isdigit(static_cast<unsigned char>(path[j])) && width < 100)
            width = width * 10 + (path[j++] - '0');
        if (j >= path.size() || path[j] != 'd' || width > 18) {
            error = fmt::format("the output name '{}' has a '%' that is not a frame number: use "
                                "%d or %04d (width and zero padding allowed), or %% for a "
                                "percent sign",
                                path);
            return std::nullopt;
        }
        if (p.numbered) {
            error = fmt::format("the output name '{}' has more than one frame number", path);
            return std::nullopt;
        }
        p.numbered = true;
        p.zeroPad = zero;
        p.width = width;
        part = &p.after;
        i = j;
    }
    return p;
}

std::string describeSeconds(double s) {
    if (s < 60) return fmt::format("{:.6g} s", s);
    if (s < 3600) {
        double m = std::floor(s / 60);
        double rest = s - 60 * m;
        return rest < 0.0005 ? fmt::format("{:g} min", m)
                             : fmt::format("{:g} min {:.3g} s", m, rest);
    }
    double h = std::floor(s / 3600);
    return fmt::format("{:g} h {:g} min", h, std::floor((s - 3600 * h) / 60));
}

} // namespace moire::clip
