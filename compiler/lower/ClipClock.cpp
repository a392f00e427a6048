#include "compiler/lower/ClipClock.h"

#include "compiler/Compile.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <vector>

namespace moire::clip {

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
    Rational period = approximate(t.period, kMaxDenominator);
    // A period under half a millisecond rounds to 0 at kMaxDenominator: read it finer.
    if (period.num == 0) period = approximate(t.period, int64_t{1} << 40);
    std::optional<Rational> c = approximate(t.delay, kMaxDenominator);
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
                std::optional<Rational> n = multiply(out.loop, f);
                if (n) whole = n->den == 1;
            }
            frames = std::max<int64_t>(1, std::llround(perLoop));
            const std::string head = fmt::format(
                "the loop is {}{}, the least common multiple of the timings' cycles ({})",
                describeSeconds(out.loop.value()),
                out.loop.den == 1 ? "" : fmt::format(" ({} s)", fractionText(out.loop)), cycles);
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
                    t->name, t->cycle(), fractionText(*cycleOf(*t)), std::fabs(off) * 100));
        }
    }
    out.frames = frames;
    return out;
}

int64_t framesBefore(double t0, double t1, double fps) {
    double x = (t1 - t0) * fps;
    if (!(x > 0)) return 0;
    double nearest = std::round(x);
    if (std::fabs(x - nearest) <= 1e-6 * std::max(1.0, x)) return static_cast<int64_t>(nearest);
    return static_cast<int64_t>(std::ceil(x));
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
