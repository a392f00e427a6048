// What the backends that write source text share (the GLSL emitter, the JavaScript frame
// backend): the IR's tree of blocks as nested blocks of a C-like language. Every value is a
// variable named after its id (v12); an If's results are variables declared before it and
// assigned at the end of each branch; a Loop is an endless loop over its carried variables
// (l<loop>_<i>) that breaks when its condition region yields false; powi is spelled by the
// binary exponentiation of Semantics.h's semPowI, so the roundings agree. Pure ops are
// spelled from a dialect's table of forms ("($0 + $1)"), in which $0, $1, $2 are the operands
// and $i the integer immediate. A dialect gives the declarations and spells the ops it
// writes its own way (constants, outputs, the ops it refuses).
#pragma once

#include "compiler/ir/IR.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace moire::backend {

// Whether a dialect's table of forms lists the ops in the order of Ops.def, one each.
template <class Form, size_t N>
constexpr bool formsFollowOps(const Form (&forms)[N]) {
    if (N != static_cast<size_t>(ir::kNumOps)) return false;
    for (size_t i = 0; i < N; ++i)
        if (static_cast<size_t>(forms[i].op) != i) return false;
    return true;
}

class StructuredText {
  public:
    struct Syntax {
        int indent = 4;                      // spaces per level
        const char* loop = "while (true) {"; // an endless loop's opening line
        const char* one = "1.0";             // the float 1 (x^0, 1 / x)
    };

  protected:
    StructuredText(const ir::Function& f, Syntax syntax) : f_(f), syntax_(syntax) {}
    virtual ~StructuredText() = default;

    // The declaration of a value assigned once ("float", "const"), and of a variable that is
    // assigned again (an If's results, a loop's carried values: "float", "let").
    virtual std::string constant(ir::Type t) const = 0;
    virtual std::string variable(ir::Type t) const = 0;
    // The form of a pure op, in the dialect's table.
    virtual const char* form(const ir::Inst& inst) const = 0;
    // Literals of the IR's constants (a double, and a 32-bit integer in the immediate's low
    // bits), and where output `slot` is written.
    virtual std::string floatLiteral(double v) const = 0;
    virtual std::string intLiteral(int64_t v) const = 0;
    virtual std::string output(int64_t slot) const = 0;
    // Writes `inst` when the dialect spells it itself and returns true; false leaves it to
    // the shared translation (constants, outputs, powi, if, loop, tally, every op by its
    // form).
    virtual bool special(const ir::Inst& inst, int depth) = 0;

    std::string v(ir::ValueId id) const;
    void line(int depth, const std::string& text);
    void define(int depth, ir::ValueId id, const std::string& expr);
    // The op's form with its operands filled in.
    std::string expression(const ir::Inst& inst) const;
    // Every instruction of block `id` but its closing yield.
    void block(ir::BlockId id, int depth);

    const ir::Function& f_;
    std::string out_;

  private:
    void instruction(const ir::Inst& inst, int depth);
    std::string powi(const ir::Inst& inst, int depth);
    std::vector<ir::ValueId> yields(ir::BlockId b) const;
    void branch(const ir::Inst& inst, ir::BlockId region, int depth);
    void loop(const ir::Inst& inst, int depth);

    Syntax syntax_;
    int loops_ = 0;
};

} // namespace moire::backend
