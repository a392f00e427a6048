#include "runtime/view/Placement.h"

#include "compiler/Compile.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <numbers>
#include <optional>

namespace moire::view {

using ast::Expr;
using ast::ExprKind;

std::string formatNumber(double v) {
    if (!std::isfinite(v)) return "0";
    if (std::fabs(v) < 5e-10) return "0";
    std::string s;
    const double a = std::fabs(v);
    if (a >= 1e-3 && a < 1e7) {
        // Seven significant digits in fixed notation (the lexer reads no exponent sign '+').
        const int decimals = std::clamp(6 - static_cast<int>(std::floor(std::log10(a))), 0, 9);
        s = fmt::format("{:.{}f}", v, decimals);
        if (s.find('.') != std::string::npos) {
            while (s.back() == '0') s.pop_back();
            if (s.back() == '.') s.pop_back();
        }
    } else {
        s = fmt::format("{:.7g}", v);
    }
    if (s == "-0") s = "0";
    return s;
}

namespace {

std::string degrees(double radians) {
    return formatNumber(radians * 180.0 / std::numbers::pi) + "deg";
}

std::string vec(double x, double y) {
    return fmt::format("({}, {})", formatNumber(x), formatNumber(y));
}

struct Vec {
    double x = 0, y = 0;
};

Vec rotated(Vec v, double a) {
    const double c = std::cos(a), s = std::sin(a);
    return {c * v.x - s * v.y, s * v.x + c * v.y};
}

class Writer {
  public:
    explicit Writer(const SceneProgram& program) : program_(program) {}

    std::string text(const Expr& e) const {
        const SourceFile& file = program_.sources->file(e.range.begin.file);
        return file.text().substr(e.range.begin.offset, e.range.length);
    }

    // A number written as a literal (possibly signed), in the language's units.
    static std::optional<double> literal(const Expr* e) {
        if (!e) return std::nullopt;
        if (e->kind == ExprKind::Number) return e->number;
        if (e->kind == ExprKind::Unary && e->args.size() == 1) {
            auto v = literal(e->args[0].get());
            if (v) return e->un == ast::UnOp::Neg ? -*v : *v;
        }
        return std::nullopt;
    }
    static std::optional<Vec> literalVec(const Expr* e) {
        if (!e || e->kind != ExprKind::Vector || e->args.size() != 2) return std::nullopt;
        auto x = literal(e->args[0].get()), y = literal(e->args[1].get());
        if (!x || !y) return std::nullopt;
        return Vec{*x, *y};
    }

    // A sub-expression's text, parenthesised unless it is a single token or call.
    std::string atom(const Expr& e) const {
        std::string t = text(e);
        if (e.kind == ExprKind::Number || e.kind == ExprKind::Name || e.kind == ExprKind::Call ||
            e.kind == ExprKind::Vector || (t.size() >= 2 && t.front() == '(' && t.back() == ')'))
            return t;
        return "(" + t + ")";
    }

    // The text of Rot(a) e for a vector expression e, written so that it stays an expression
    // of the clock wherever e was: the turn goes through sums, scalings and the ends of
    // ramps and mixes (affine in their ends) down to literals or component pairs. Empty when
    // e is something the language cannot turn (a vector-valued name, say).
    std::string turned(const Expr& e, double a) const {
        if (auto v = literalVec(&e)) {
            Vec r = rotated(*v, a);
            return vec(r.x, r.y);
        }
        const std::string c = formatNumber(std::cos(a)), s = formatNumber(std::sin(a));
        switch (e.kind) {
        case ExprKind::Vector:
            if (e.args.size() != 2) return {};
            return "(" + c + " * " + atom(*e.args[0]) + " - " + s + " * " + atom(*e.args[1]) +
                   ", " + s + " * " + atom(*e.args[0]) + " + " + c + " * " + atom(*e.args[1]) + ")";
        case ExprKind::Call:
            if ((e.name == "ramp" || e.name == "mix") && e.args.size() == 3) {
                const int first = e.name == "ramp" ? 1 : 0; // ramp(timing, from, to)
                std::string ends[2];
                for (int k = 0; k < 2; ++k) {
                    ends[k] = turned(*e.args[first + k], a);
                    if (ends[k].empty()) return {};
                }
                if (e.name == "ramp")
                    return "ramp(" + text(*e.args[0]) + ", " + ends[0] + ", " + ends[1] + ")";
                return "mix(" + ends[0] + ", " + ends[1] + ", " + text(*e.args[2]) + ")";
            }
            return {};
        case ExprKind::Binary: {
            const Expr& l = *e.args[0];
            const Expr& r = *e.args[1];
            if (e.bin == ast::BinOp::Add || e.bin == ast::BinOp::Sub) {
                std::string lt = turned(l, a), rt = turned(r, a);
                if (lt.empty() || rt.empty()) return {};
                return lt + (e.bin == ast::BinOp::Add ? " + " : " - ") + "(" + rt + ")";
            }
            const bool leftVec = l.type == ast::Type::Vec2;
            if (e.bin == ast::BinOp::Mul || e.bin == ast::BinOp::Div) {
                std::string vt = turned(leftVec ? l : r, a);
                if (vt.empty()) return {};
                if (leftVec)
                    return "(" + vt + ")" + (e.bin == ast::BinOp::Mul ? " * " : " / ") + atom(r);
                return atom(l) + " * (" + vt + ")";
            }
            return {};
        }
        case ExprKind::Unary: {
            std::string t = turned(*e.args[0], a);
            if (t.empty()) return {};
            return e.un == ast::UnOp::Neg ? "-(" + t + ")" : t;
        }
        default:
            return {};
        }
    }

    std::string camera(const ViewAdjust& view) const {
        const ast::Decl* cam = program_.checked.camera;
        const Expr* center =
            cam && cam->prop("center") ? cam->prop("center")->value.get() : nullptr;
        const Expr* zoom = cam && cam->prop("zoom") ? cam->prop("zoom")->value.get() : nullptr;
        const Expr* turn =
            cam && cam->prop("rotation") ? cam->prop("rotation")->value.get() : nullptr;

        std::string out = "camera { center = ";
        if (!center || literalVec(center)) {
            Vec c = center ? *literalVec(center) : Vec{};
            out += vec(c.x + view.panX, c.y + view.panY);
        } else {
            out += text(*center);
            if (view.panX != 0.0 || view.panY != 0.0) out += " + " + vec(view.panX, view.panY);
        }
        out += "; zoom = ";
        if (!zoom || literal(zoom)) {
            out += formatNumber((zoom ? *literal(zoom) : 1.0) * view.zoomFactor);
        } else {
            const bool sum = zoom->kind == ExprKind::Binary &&
                             (zoom->bin == ast::BinOp::Add || zoom->bin == ast::BinOp::Sub);
            out += sum ? "(" + text(*zoom) + ")" : text(*zoom);
            if (view.zoomFactor != 1.0) out += " * " + formatNumber(view.zoomFactor);
        }
        if (turn) out += "; rotation = " + text(*turn); // the viewer never turns the camera
        return out + "; }\n";
    }

    // Layer i moved by m: its points go from p to Rot(m.turn) p + d, so its origin o becomes
    // Rot(m.turn) o + d and its rotation gains m.turn.
    std::string layer(int i, const LayerMotion& m) const {
        const sema::CheckedLayer& layer = program_.checked.layers[i];
        const Expr* origin = layer.prop("origin");
        const Expr* turn = layer.prop("rotation");
        std::string note;

        std::string o;
        if (!origin || literalVec(origin)) {
            Vec v = rotated(origin ? *literalVec(origin) : Vec{}, m.turn);
            o = vec(v.x + m.dx, v.y + m.dy);
        } else {
            o = m.turn == 0.0 ? text(*origin) : turned(*origin, m.turn);
            if (o.empty()) {
                // Cannot be turned in the language: keep the scene's text and say what to do.
                o = text(*origin);
                note = fmt::format("  // turn the origin by {} about (0, 0), then add {}",
                                   degrees(m.turn), vec(m.dx, m.dy));
            } else if (m.dx != 0.0 || m.dy != 0.0) {
                o += " + " + vec(m.dx, m.dy);
            }
        }

        std::string r;
        if (!turn || literal(turn)) {
            r = degrees((turn ? *literal(turn) : 0.0) + m.turn);
        } else {
            r = text(*turn);
            if (m.turn != 0.0) {
                const double deg = m.turn * 180.0 / std::numbers::pi;
                r += (deg < 0 ? " - " : " + ") + degrees(std::fabs(m.turn));
            }
        }

        const std::string& name = layer.decl->name;
        std::string head = name.empty() ? "layer" : "layer " + name;
        std::string line = head + " { origin = " + o + "; rotation = " + r + " }";
        if (name.empty()) line += fmt::format("  // layer {} (unnamed)", i + 1);
        return line + note + "\n";
    }

  private:
    const SceneProgram& program_;
};

} // namespace

std::string placementText(const SceneProgram& program, const ViewAdjust& view) {
    Writer w(program);
    std::string out = w.camera(view);
    const int n = static_cast<int>(program.checked.layers.size());
    for (int i = 0; i < n; ++i)
        if (!view.layer(i).identity()) out += w.layer(i, view.layer(i));
    return out;
}

} // namespace moire::view
