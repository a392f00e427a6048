// An IR value together with the builder that makes it, so that maths written once as a
// template over the number type (Plane.h, lower/CameraModel.h, the stroke band) builds IR
// when instantiated with it, and computes directly when instantiated with double. Each
// operator appends the one op it names: no folding, no reordering.
#pragma once

#include "compiler/ir/Builder.h"

namespace moire::ir {

struct BuiltValue {
    Builder* b = nullptr;
    ValueId id = kNoValue;
    BuiltValue() = default;
    BuiltValue(Builder& builder, ValueId v) : b(&builder), id(v) {}
    // (No conversion back to ValueId: a comparison of two of these would compare ids.)
    // A number of the formula, as a constant of the function being built.
    BuiltValue constant(double v) const { return {*b, b->constF(v)}; }
};

inline BuiltValue operator+(BuiltValue x, BuiltValue y) {
    return {*x.b, x.b->add(x.id, y.id)};
}
inline BuiltValue operator-(BuiltValue x, BuiltValue y) {
    return {*x.b, x.b->sub(x.id, y.id)};
}
inline BuiltValue operator*(BuiltValue x, BuiltValue y) {
    return {*x.b, x.b->mul(x.id, y.id)};
}
inline BuiltValue operator/(BuiltValue x, BuiltValue y) {
    return {*x.b, x.b->div(x.id, y.id)};
}
inline BuiltValue operator-(BuiltValue x) {
    return {*x.b, x.b->neg(x.id)};
}
inline BuiltValue operator+(BuiltValue x, double y) {
    return x + x.constant(y);
}
inline BuiltValue operator-(BuiltValue x, double y) {
    return x - x.constant(y);
}
inline BuiltValue operator*(BuiltValue x, double y) {
    return x * x.constant(y);
}
inline BuiltValue operator/(BuiltValue x, double y) {
    return x / x.constant(y);
}
inline BuiltValue operator-(double x, BuiltValue y) {
    return y.constant(x) - y;
}
inline BuiltValue max(BuiltValue x, BuiltValue y) {
    return {*x.b, x.b->max(x.id, y.id)};
}
inline BuiltValue min(BuiltValue x, BuiltValue y) {
    return {*x.b, x.b->min(x.id, y.id)};
}
inline BuiltValue cos(BuiltValue x) {
    return {*x.b, x.b->cos(x.id)};
}
inline BuiltValue sin(BuiltValue x) {
    return {*x.b, x.b->sin(x.id)};
}
inline BuiltValue asin(BuiltValue x) {
    return {*x.b, x.b->emit(Op::Asin, {x.id})};
}
inline BuiltValue sqrt(BuiltValue x) {
    return {*x.b, x.b->sqrt(x.id)};
}
inline BuiltValue operator*(double x, BuiltValue y) {
    return y.constant(x) * y;
}
inline BuiltValue abs(BuiltValue x) {
    return {*x.b, x.b->abs(x.id)};
}
inline BuiltValue floor(BuiltValue x) {
    return {*x.b, x.b->floor(x.id)};
}
inline BuiltValue hypot(BuiltValue x, BuiltValue y) {
    return {*x.b, x.b->hypot(x.id, y.id)};
}
inline BuiltValue atan2(BuiltValue y, BuiltValue x) {
    return {*y.b, y.b->emit(Op::Atan2, {y.id, x.id})};
}

// Branch-free choices, for maths that must stay straight-line IR: a comparison gives a
// boolean value, and select picks by it. The double overloads are the same choices made
// directly (call them qualified, ir::select, so that a template finds both).
inline BuiltValue lessThan(BuiltValue x, BuiltValue y) {
    return {*x.b, x.b->lt(x.id, y.id)};
}
inline BuiltValue select(BuiltValue cond, BuiltValue x, BuiltValue y) {
    return {*x.b, x.b->select(cond.id, x.id, y.id)};
}
inline bool lessThan(double x, double y) {
    return x < y;
}
inline double select(bool cond, double x, double y) {
    return cond ? x : y;
}
// The number v in the kind of `like`: a constant of the function being built, or v itself.
inline BuiltValue literal(BuiltValue like, double v) {
    return like.constant(v);
}
inline double literal(double, double v) {
    return v;
}

} // namespace moire::ir
