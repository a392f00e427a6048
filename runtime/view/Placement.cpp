#include "runtime/view/Placement.h"

#include "compiler/Compile.h"
#include "compiler/ir/Plane.h"

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
    const ir::Vec2T<double> r = ir::rotate<double>({v.x, v.y}, a);
    return {r.x, r.y};
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

    // The camera's center and zoom with the view's pan and zoom applied, and its rotation
    // as the scene writes it (empty when it writes none: the viewer never turns the camera).
    struct CameraValues {
        std::string center, zoom, rotation;
    };
    CameraValues camera(const ViewAdjust& view) const {
        const ast::Decl* cam = program_.checked.camera;
        const Expr* center =
            cam && cam->prop("center") ? cam->prop("center")->value.get() : nullptr;
        const Expr* zoom = cam && cam->prop("zoom") ? cam->prop("zoom")->value.get() : nullptr;
        const Expr* turn =
            cam && cam->prop("rotation") ? cam->prop("rotation")->value.get() : nullptr;

        CameraValues out;
        if (!center || literalVec(center)) {
            Vec c = center ? *literalVec(center) : Vec{};
            out.center = vec(c.x + view.panX, c.y + view.panY);
        } else {
            out.center = text(*center);
            if (view.panX != 0.0 || view.panY != 0.0)
                out.center += " + " + vec(view.panX, view.panY);
        }
        if (!zoom || literal(zoom)) {
            out.zoom = formatNumber((zoom ? *literal(zoom) : 1.0) * view.zoomFactor);
        } else {
            const bool sum = zoom->kind == ExprKind::Binary &&
                             (zoom->bin == ast::BinOp::Add || zoom->bin == ast::BinOp::Sub);
            out.zoom = sum ? "(" + text(*zoom) + ")" : text(*zoom);
            if (view.zoomFactor != 1.0) out.zoom += " * " + formatNumber(view.zoomFactor);
        }
        if (turn) out.rotation = text(*turn);
        return out;
    }

    // Layer i moved by m: its points go from p to Rot(m.turn) p + d, so its origin o becomes
    // Rot(m.turn) o + d and its rotation gains m.turn. `note` is set when the origin is an
    // expression the language cannot turn: `origin` is then the scene's text, unturned.
    struct LayerValues {
        std::string origin, rotation, note;
    };
    LayerValues layer(int i, const LayerMotion& m) const {
        const sema::CheckedLayer& layer = program_.checked.layers[i];
        const Expr* origin = layer.prop("origin");
        const Expr* turn = layer.prop("rotation");
        LayerValues out;

        std::string& o = out.origin;
        if (!origin || literalVec(origin)) {
            Vec v = rotated(origin ? *literalVec(origin) : Vec{}, m.turn);
            o = vec(v.x + m.dx, v.y + m.dy);
        } else {
            o = m.turn == 0.0 ? text(*origin) : turned(*origin, m.turn);
            if (o.empty()) {
                o = text(*origin);
                out.note = fmt::format("turn the origin by {} about (0, 0), then add {}",
                                       degrees(m.turn), vec(m.dx, m.dy));
            } else if (m.dx != 0.0 || m.dy != 0.0) {
                o += " + " + vec(m.dx, m.dy);
            }
        }

        std::string& r = out.rotation;
        if (!turn || literal(turn)) {
            r = degrees((turn ? *literal(turn) : 0.0) + m.turn);
        } else {
            r = text(*turn);
            if (m.turn != 0.0) {
                const double deg = m.turn * 180.0 / std::numbers::pi;
                r += (deg < 0 ? " - " : " + ") + degrees(std::fabs(m.turn));
            }
        }
        return out;
    }

  private:
    const SceneProgram& program_;
};

} // namespace

std::string placementText(const SceneProgram& program, const ViewAdjust& view) {
    Writer w(program);
    const Writer::CameraValues cam = w.camera(view);
    std::string out = "camera { center = " + cam.center + "; zoom = " + cam.zoom;
    if (!cam.rotation.empty()) out += "; rotation = " + cam.rotation;
    out += "; }\n";
    const int n = static_cast<int>(program.checked.layers.size());
    for (int i = 0; i < n; ++i) {
        if (view.layer(i).identity()) continue;
        const Writer::LayerValues l = w.layer(i, view.layer(i));
        const std::string& name = program.checked.layers[i].decl->name;
        out += (name.empty() ? std::string("layer") : "layer " + name) + " { origin = " + l.origin +
               "; rotation = " + l.rotation + " }";
        if (name.empty()) out += fmt::format("  // layer {} (unnamed)", i + 1);
        if (!l.note.empty()) out += "  // " + l.note;
        out += "\n";
    }
    return out;
}

namespace {

// A replacement of `length` bytes at `offset` of the scene's text.
struct Edit {
    size_t offset, length;
    std::string text;
    size_t order = 0; // insertions at one offset keep the order they were made in
};

// Sets property `name` of the block `decl` to `value`: the value's text replaced where the
// block writes one, else the property added first in the block.
void setProperty(const std::string& source, const ast::Decl& decl, const char* name,
                 const std::string& value, std::vector<Edit>& edits) {
    if (const ast::Property* p = decl.prop(name)) {
        edits.push_back({p->value->range.begin.offset, p->value->range.length, value});
        return;
    }
    const size_t open = source.find('{', decl.range.begin.offset);
    if (open == std::string::npos) return;
    edits.push_back({open + 1, 0, fmt::format(" {} = {};", name, value)});
}

} // namespace

bool placedSource(const SceneProgram& program, const ViewAdjust& view, std::string& out,
                  std::string& why) {
    const SourceFile& file = program.sources->file(program.userModule().file);
    const std::string& source = file.text();
    Writer w(program);
    std::vector<Edit> edits;

    const bool moved = view.panX != 0.0 || view.panY != 0.0 || view.zoomFactor != 1.0;
    if (moved) {
        const Writer::CameraValues cam = w.camera(view);
        if (const ast::Decl* decl = program.checked.camera) {
            if (view.panX != 0.0 || view.panY != 0.0)
                setProperty(source, *decl, "center", cam.center, edits);
            if (view.zoomFactor != 1.0) setProperty(source, *decl, "zoom", cam.zoom, edits);
        } else {
            // A new block on its own line before the first layer (or at the end).
            size_t at = source.size();
            if (!program.checked.layers.empty()) {
                at = program.checked.layers[0].decl->range.begin.offset;
                const size_t nl = source.rfind('\n', at == 0 ? 0 : at - 1);
                at = at == 0 || nl == std::string::npos ? 0 : nl + 1;
            }
            std::string block = "camera { center = " + cam.center + "; zoom = " + cam.zoom + " }\n";
            if (at == source.size() && !source.empty() && source.back() != '\n')
                block = "\n" + block;
            edits.push_back({at, 0, block});
        }
    }
    const int n = static_cast<int>(program.checked.layers.size());
    for (int i = 0; i < n; ++i) {
        const LayerMotion& m = view.layer(i);
        if (m.identity()) continue;
        const Writer::LayerValues l = w.layer(i, m);
        const ast::Decl& decl = *program.checked.layers[i].decl;
        if (!l.note.empty()) {
            why = fmt::format("the origin of layer {} is an expression that cannot be turned in "
                              "the language: {}",
                              decl.name.empty() ? std::to_string(i + 1) : "'" + decl.name + "'",
                              l.note);
            return false;
        }
        if (m.dx != 0.0 || m.dy != 0.0 || m.turn != 0.0)
            setProperty(source, decl, "origin", l.origin, edits);
        if (m.turn != 0.0) setProperty(source, decl, "rotation", l.rotation, edits);
    }
    // From the end, so that each edit's offset still holds when it is made.
    for (size_t i = 0; i < edits.size(); ++i) edits[i].order = i;
    std::sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) {
        return a.offset != b.offset ? a.offset > b.offset : a.order > b.order;
    });
    out = source;
    for (const Edit& e : edits) out.replace(e.offset, e.length, e.text);
    return true;
}

} // namespace moire::view
