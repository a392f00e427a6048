// The properties each block accepts (scene, camera, layer): name, type, what it may depend
// on, and the value it takes when the scene does not write it. One table, read by the checks
// (Sema.cpp: what may be written) and by the lowering (what an unwritten property means).
#pragma once

#include "compiler/parse/Ast.h"

#include <string>
#include <string_view>
#include <vector>

namespace moire::sema {

// The frame a scene without `size` is drawn in, in pixels.
constexpr double kDefaultWidth = 1200, kDefaultHeight = 800;

// One property a block accepts.
struct PropertySpec {
    const char* name;
    ast::Type type;
    bool positionFree; // may not depend on x, y
    bool timeFree;     // may not depend on t
    const char* doc;
    // The value of the property when it is not written, one number per component (a colour
    // is r, g, b, a in 0..1; an angle is in radians). Empty: none (the property changes what
    // is drawn only when written: `family`, `field`).
    std::vector<double> defaults = {};
};
const std::vector<PropertySpec>& sceneProperties();
const std::vector<PropertySpec>& cameraProperties();
const std::vector<PropertySpec>& layerProperties(); // `family` is listed with type Error
// A timing's properties; `mode` and `easing` are names, listed with type Error.
const std::vector<PropertySpec>& timingProperties();
// The properties of a family's body (its parameters and lets are the family's own).
const std::vector<PropertySpec>& familyProperties();
// The names of a table's properties, in order (for "did you mean" and an editor's lists).
std::vector<std::string> propertyNames(const std::vector<PropertySpec>& table);

// The names of a timing's and a family body's properties (those tables' names), and a timing's
// modes: for Sema.cpp's suggestions and the tools that name them (`moire names`, the editor
// packages).
const std::vector<std::string>& timingPropertyNames();     // period, delay, mode, easing
const std::vector<std::string>& familyBodyPropertyNames(); // phase, first, facets, distance, index
const std::vector<std::string>& timingModeNames();         // once, loop, pingpong

// The entry for `name` in `table`; an internal error when there is none (a bug in moire).
const PropertySpec& propertySpec(const std::vector<PropertySpec>& table, std::string_view name);

} // namespace moire::sema
