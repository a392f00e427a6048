// The meaning of every pure IR op on scalars, written once as a template. The interpreter
// instantiates it with double, the constant folder with double, and the backend tests with
// float to hold the JIT to the same definition. The LLVM and GLSL backends emit these same
// formulas (including the clamps at singular points), so a pole is the same finite number
// on every backend rather than a NaN on one of them.
#pragma once

#include "compiler/ir/IR.h"

#include <cmath>
#include <cstdint>
#include <limits>

namespace moire::ir {

// Guards used at singular points. Both are normal numbers in single precision.
constexpr double kTiny = 1e-30;      // log argument floor; denominators of atan2/hypot rules
constexpr double kSqrtFloor = 1e-18; // floor of sqrt(x) in d sqrt(x) = dx / (2 sqrt(x))
constexpr int64_t kIntClamp = int64_t(1) << 30;

template <class T>
inline T semMin(T a, T b) {
    return b < a ? b : a;
}
template <class T>
inline T semMax(T a, T b) {
    return b > a ? b : a;
}
template <class T>
inline T semPowI(T x, int64_t n) {
    T base = n < 0 ? T(1) / x : x;
    uint64_t e = static_cast<uint64_t>(n < 0 ? -n : n);
    T r = T(1);
    while (e) {
        if (e & 1) r *= base;
        base *= base;
        e >>= 1;
    }
    return r;
}
template <class T>
inline int32_t semFToI(T x) {
    if (!(x == x)) return 0;
    T f = std::floor(x);
    if (f > T(kIntClamp)) return static_cast<int32_t>(kIntClamp);
    if (f < T(-kIntClamp)) return static_cast<int32_t>(-kIntClamp);
    return static_cast<int32_t>(f);
}

// Evaluates a pure op whose operands and result are floats.
template <class T>
inline T evalFloat(Op op, const T* a, int64_t iimm) {
    switch (op) {
    case Op::Add:
        return a[0] + a[1];
    case Op::Sub:
        return a[0] - a[1];
    case Op::Mul:
        return a[0] * a[1];
    case Op::MulZ:
        return (a[0] == T(0) || a[1] == T(0)) ? T(0) : a[0] * a[1];
    case Op::Div:
        return a[0] / a[1];
    case Op::Neg:
        return -a[0];
    case Op::Abs:
        return std::fabs(a[0]);
    case Op::Sign:
        return a[0] > T(0) ? T(1) : (a[0] < T(0) ? T(-1) : T(0));
    case Op::Floor:
        return std::floor(a[0]);
    case Op::Round:
        return std::floor(a[0] + T(0.5));
    case Op::Fract:
        return a[0] - std::floor(a[0]);
    case Op::Mod:
        return a[0] - a[1] * std::floor(a[0] / a[1]);
    case Op::Min:
        return semMin(a[0], a[1]);
    case Op::Max:
        return semMax(a[0], a[1]);
    case Op::Sqrt:
        return std::sqrt(semMax(a[0], T(0)));
    case Op::Exp:
        return std::exp(a[0]);
    case Op::Log:
        return std::log(semMax(a[0], T(kTiny)));
    case Op::Pow:
        return std::pow(a[0], a[1]);
    case Op::PowI:
        return semPowI(a[0], iimm);
    case Op::Sin:
        return std::sin(a[0]);
    case Op::Cos:
        return std::cos(a[0]);
    case Op::Tan:
        return std::tan(a[0]);
    case Op::Asin:
        return std::asin(semMin(semMax(a[0], T(-1)), T(1)));
    case Op::Acos:
        return std::acos(semMin(semMax(a[0], T(-1)), T(1)));
    case Op::Atan:
        return std::atan(a[0]);
    case Op::Atan2:
        return std::atan2(a[0], a[1]);
    case Op::Hypot:
        return std::hypot(a[0], a[1]);
    default:
        return std::numeric_limits<T>::quiet_NaN();
    }
}

// Evaluates a pure op with a boolean result over float operands.
template <class T>
inline bool evalCompare(Op op, T a, T b) {
    switch (op) {
    case Op::Lt:
        return a < b;
    case Op::Le:
        return a <= b;
    case Op::Gt:
        return a > b;
    case Op::Ge:
        return a >= b;
    case Op::Eq:
        return a == b;
    case Op::Ne:
        return a != b;
    default:
        return false;
    }
}

inline bool isFloatOp(Op op) {
    switch (op) {
    case Op::Add:
    case Op::Sub:
    case Op::Mul:
    case Op::MulZ:
    case Op::Div:
    case Op::Neg:
    case Op::Abs:
    case Op::Sign:
    case Op::Floor:
    case Op::Round:
    case Op::Fract:
    case Op::Mod:
    case Op::Min:
    case Op::Max:
    case Op::Sqrt:
    case Op::Exp:
    case Op::Log:
    case Op::Pow:
    case Op::PowI:
    case Op::Sin:
    case Op::Cos:
    case Op::Tan:
    case Op::Asin:
    case Op::Acos:
    case Op::Atan:
    case Op::Atan2:
    case Op::Hypot:
        return true;
    default:
        return false;
    }
}

inline bool isCompareOp(Op op) {
    return op == Op::Lt || op == Op::Le || op == Op::Gt || op == Op::Ge || op == Op::Eq ||
           op == Op::Ne;
}

} // namespace moire::ir
