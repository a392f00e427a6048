// Stage (a): source -> lexer and parser. The parser must turn any bytes into a module and
// diagnostics that point into the text. A module that parses cleanly prints (printExpr) as
// fully parenthesised text that parses back to the same print.
#include "compiler/parse/Parser.h"
#include "fuzz/FuzzSupport.h"

#include <algorithm>
#include <string_view>

namespace {
using namespace moire;

// printExpr's text is source again except for degrees, which it spells `1rad(deg)`.
void roundTrip(const ast::Expr& e) {
    std::string once = printExpr(e);
    if (once.find("rad(deg)") != std::string::npos) return;
    SourceManager sm;
    DiagEngine diags(sm);
    uint32_t id = sm.add("print.moire", once);
    ast::ExprPtr again = Parser(sm, id, diags).parseStandaloneExpr();
    // The print parenthesises every operation, so it nests deeper than the source did (a
    // sign and its parenthesis are two levels where the source's sign was one); past the
    // parser's limit it is refused for that alone, which is not a finding (a chain of 127
    // signs under the limit prints 254 levels deep, and more with its operand).
    const auto& all = diags.all();
    if (!all.empty() && std::all_of(all.begin(), all.end(), [](const Diagnostic& d) {
            return d.severity != Severity::Error || d.msg == Msg::TooDeep;
        }))
        return;
    if (diags.hasErrors())
        fuzz::finding("printed expression does not parse: " + once + "\n" + diags.render());
    std::string twice = printExpr(*again);
    if (twice != once) fuzz::finding("printed expression changes: " + once + " -> " + twice);
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > fuzz::kMaxInput) return -1;
    std::string text(reinterpret_cast<const char*>(data), size);
    fuzz::guarded("parse", [&] {
        auto front = fuzz::runFront(text, /*check=*/false);
        fuzz::checkDiagnostics(*front);
        (void)front->diags->render();
        const ast::Module& m = *front->modules.back();
        (void)printModule(m);
        if (!front->diags->hasErrors()) {
            for (const ast::DeclPtr& d : m.decls) {
                if (d->value) roundTrip(*d->value);
                for (const ast::Let& l : d->lets) roundTrip(*l.value);
                for (const ast::Property& p : d->props) roundTrip(*p.value);
                for (const ast::FamilyParam& p : d->params)
                    if (p.defaultValue) roundTrip(*p.defaultValue);
            }
        }
        // The same bytes as one expression (the entry point tests and tools use).
        SourceManager sm;
        DiagEngine diags(sm);
        uint32_t id = sm.add("expr.moire", text);
        ast::ExprPtr e = Parser(sm, id, diags).parseStandaloneExpr();
        if (!e) fuzz::finding("parseStandaloneExpr returned null");
        (void)diags.render();
    });
    return 0;
}
