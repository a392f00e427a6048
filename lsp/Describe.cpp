#include "lsp/Describe.h"

#include <fmt/format.h>

namespace moire::lsp {

using sema::Signature;

namespace {

// The source text of a range of a file of the program.
std::string_view sourceText(const SceneProgram& program, SourceRange r) {
    const std::string& text = program.sources->file(r.begin.file).text();
    if (r.begin.offset >= text.size()) return {};
    return std::string_view(text).substr(r.begin.offset, r.length);
}

// The `//` comment lines right above the line at `offset`, without their slashes.
std::string commentAbove(std::string_view text, uint32_t offset) {
    size_t lineStart = text.rfind('\n', offset == 0 ? 0 : offset - 1);
    std::vector<std::string_view> lines;
    while (lineStart != std::string_view::npos && lineStart > 0) {
        size_t prev = text.rfind('\n', lineStart - 1);
        size_t from = prev == std::string_view::npos ? 0 : prev + 1;
        std::string_view line = text.substr(from, lineStart - from);
        while (!line.empty() && (line.front() == ' ' || line.front() == '\t'))
            line.remove_prefix(1);
        if (!line.starts_with("//")) break;
        line.remove_prefix(2);
        if (line.starts_with(" ")) line.remove_prefix(1);
        lines.push_back(line);
        if (prev == std::string_view::npos) break;
        lineStart = prev;
    }
    std::string out;
    for (auto it = lines.rbegin(); it != lines.rend(); ++it) {
        if (!out.empty()) out += ' ';
        out += *it;
    }
    return out;
}

std::string args(int n, const char* type) {
    static const char* names[] = {"a", "b", "c", "d"};
    std::string out;
    for (int i = 0; i < n && i < 4; ++i)
        out += fmt::format("{}{}: {}", i ? ", " : "", n == 1 ? "v" : names[i], type);
    return out;
}

} // namespace

std::string typeWithUnits(ast::Type t) {
    switch (t) {
    case ast::Type::Num:
        return "a number";
    case ast::Type::Angle:
        return "an angle (write deg or rad: 30deg, 0.5rad)";
    case ast::Type::Vec2:
        return "a vector (x, y)";
    case ast::Type::Color:
        return "a colour (#rrggbb, #rrggbbaa, rgb(...) or rgba(...))";
    case ast::Type::Bool:
        return "a boolean (true or false)";
    case ast::Type::Error:
        return "a name";
    }
    return "a value";
}

Description describeFunction(const sema::FnInfo& fn) {
    std::string sig;
    switch (fn.sig) {
    case Signature::Trig:
        sig = fmt::format("{}(v: number | angle) -> number", fn.spelling);
        break;
    case Signature::NumToNum:
        sig = fmt::format("{}({}) -> number", fn.spelling, args(fn.numArgs, "number"));
        break;
    case Signature::SameUnit:
        sig =
            fmt::format("{}({}) -> T, T a number or an angle", fn.spelling, args(fn.numArgs, "T"));
        break;
    case Signature::SameToNum:
        sig = fmt::format("{}({}) -> number, T a number or an angle", fn.spelling,
                          args(fn.numArgs, "T"));
        break;
    case Signature::Mix:
        sig = fmt::format("{}(a: T, b: T, u: number) -> T, T any value", fn.spelling);
        break;
    case Signature::Length:
        sig = fmt::format("{}(v: vector) -> number", fn.spelling);
        break;
    case Signature::Color:
        sig = fmt::format("{}({}) -> colour", fn.spelling, args(fn.numArgs, "number"));
        break;
    case Signature::Timed:
        sig = fn.numArgs == 1 ? fmt::format("{}(timing) -> number", fn.spelling)
                              : fmt::format("{}(timing, from: T, to: T) -> T", fn.spelling);
        break;
    case Signature::Select:
        sig = fmt::format("{}(b: boolean, a: T, c: T) -> T, T any value", fn.spelling);
        break;
    }
    return {sig, fn.doc};
}

Description describeBuiltinName(const sema::NameInfo& name) {
    std::string type = std::string_view(name.spelling) == "theta" ? "angle" : "number";
    std::string note = name.position ? " (depends on the position)"
                       : name.time   ? " (depends on the clock)"
                                     : " (a constant)";
    return {fmt::format("{}: {}", name.spelling, type), std::string(name.what) + note};
}

Description describeProperty(const sema::PropertySpec& spec, const char* block) {
    std::string sig = fmt::format("{} = {}", spec.name, typeWithUnits(spec.type));
    std::string meaning = fmt::format("{} (a property of {}", spec.doc, block);
    if (!spec.defaults.empty()) {
        std::string d;
        for (size_t i = 0; i < spec.defaults.size(); ++i)
            d += fmt::format("{}{}", i ? ", " : "", spec.defaults[i]);
        meaning += fmt::format("; default {}{}{}", spec.defaults.size() > 1 ? "(" : "", d,
                               spec.defaults.size() > 1 ? ")" : "");
    }
    if (spec.positionFree && spec.timeFree)
        meaning += "; may not depend on the position or the clock";
    else if (spec.positionFree)
        meaning += "; may not depend on the position";
    return {sig, meaning + ")"};
}

Description describeDecl(const SceneProgram& program, const ast::Decl& decl) {
    const std::string& text = program.sources->file(decl.range.begin.file).text();
    size_t start = decl.range.begin.offset;
    size_t eol = text.find('\n', start);
    std::string line = text.substr(start, eol == std::string::npos ? eol : eol - start);
    if (line.ends_with(" {")) line.resize(line.size() - 2); // the body follows
    if (line.size() > 200) line = line.substr(0, 200) + " ...";
    return {line, commentAbove(text, decl.range.begin.offset)};
}

Description describeParam(const SceneProgram& program, const ast::Decl& family, int index) {
    const ast::FamilyParam& p = family.params.at(index);
    std::string sig = fmt::format("{} = {}", p.name, typeWithUnits(p.type));
    std::string meaning = fmt::format("a parameter of the family {}", family.name);
    if (p.defaultValue)
        meaning += fmt::format(" (default {})", sourceText(program, p.defaultValue->range));
    else
        meaning += " (no default: a layer must set it)";
    return {sig, meaning};
}

Description describeSceneParam(const SceneProgram& program, const ast::Decl& p) {
    auto written = [&](const ast::ExprPtr& e) {
        std::string s(e ? sourceText(program, e->range) : std::string_view("?"));
        return s.size() > 80 ? s.substr(0, 80) + " ..." : s;
    };
    std::string sig = fmt::format("param {} = {}", p.name, written(p.value));
    std::string meaning =
        fmt::format("a param: {}", p.value ? typeWithUnits(p.value->type) : "a value");
    if (p.rangeLo && p.rangeHi) {
        sig += fmt::format(" in {} .. {}", written(p.rangeLo), written(p.rangeHi));
        meaning +=
            fmt::format(", from {} to {}{}", written(p.rangeLo), written(p.rangeHi),
                        p.value && p.value->type == ast::Type::Vec2 ? " (each component)" : "");
    }
    if (p.step) {
        sig += " step " + written(p.step);
        meaning += ", in steps of " + written(p.step);
    }
    if (!p.unitLabel.empty()) {
        sig += " unit " + p.unitLabel;
        meaning += ", shown in " + p.unitLabel;
    }
    meaning += fmt::format(". A slider turns it; `-D {}=VALUE` sets it", p.name);
    const std::string& text = program.sources->file(p.range.begin.file).text();
    std::string comment = commentAbove(text, p.range.begin.offset);
    return {sig, comment.empty() ? meaning : comment + "\n\n" + meaning};
}

Description describeParamClause(std::string_view word) {
    if (word == "in")
        return {"in lo .. hi", "the range a param's slider covers; a value outside it is an error "
                               "(ends are constants of the param's type)"};
    if (word == "step") return {"step s", "the step of a param's slider (more than 0)"};
    return {"unit word", "a label shown beside a param's slider (px, mm, s...); it does not "
                         "change the value"};
}

const std::vector<sema::PropertySpec>* propertyTable(ast::DeclKind kind) {
    switch (kind) {
    case ast::DeclKind::Scene:
        return &sema::sceneProperties();
    case ast::DeclKind::Camera:
        return &sema::cameraProperties();
    case ast::DeclKind::Layer:
        return &sema::layerProperties();
    case ast::DeclKind::Timing:
        return &sema::timingProperties();
    case ast::DeclKind::Family:
        return &sema::familyProperties();
    default:
        return nullptr;
    }
}

} // namespace moire::lsp
