#include "compiler/sema/Properties.h"

#include "compiler/diag/Diagnostics.h"

namespace moire::sema {

using ast::Type;

const std::vector<PropertySpec>& sceneProperties() {
    static const std::vector<PropertySpec> props = {
        {"size",
         Type::Vec2,
         true,
         true,
         "image size in pixels, (width, height)",
         {kDefaultWidth, kDefaultHeight}},
        {"background", Type::Color, true, false, "paper colour (white)", {1, 1, 1, 1}},
        // Transparent: no tint unless the scene sets one.
        {"unresolved",
         Type::Color,
         true,
         false,
         "tint laid where an encoded field's fringes are too fine for its carrier",
         {0, 0, 0, 0}},
        // A view's name (sema/Views.h), checked by name rather than as an expression.
        {"view", Type::Error, true, true, "what is drawn: pattern, envelope, split or ratio"},
        // A switch, checked by name: true or false.
        {"overlay", Type::Error, true, true,
         "true: the fringe curves of the winning character, laid over the view where a "
         "fringe stands"},
        // A filter's name (sema/Views.h), checked by name.
        {"filter", Type::Error, true, true,
         "how strokes are sampled: point (at the pixel's centre) or mean (averaged over the "
         "pixel where members are finer than pixels)"},
        {"envelope_gain",
         Type::Num,
         true,
         false,
         "contrast of the envelope about its pivot (the mean the layers would have apart)",
         {3}},
        {"envelope_taps",
         Type::Num,
         true,
         false,
         "the envelope's taps: index steps averaged over one period (rounded, 1 to 1024)",
         {24}},
    };
    return props;
}

const std::vector<PropertySpec>& cameraProperties() {
    static const std::vector<PropertySpec> props = {
        {"center", Type::Vec2, true, false, "world point at the middle of the image", {0, 0}},
        {"zoom", Type::Num, true, false, "pixels per world unit", {1}},
        {"rotation", Type::Angle, true, false, "turn of the view", {0}},
    };
    return props;
}

const std::vector<PropertySpec>& layerProperties() {
    static const std::vector<PropertySpec> props = {
        {"family", Type::Error, false, false, "a family name, or a phase expression in x and y"},
        {"spacing", Type::Num, false, false, "distance between members (s)", {10}},
        {"phase", Type::Num, false, false, "offset of the members, in phase units", {0}},
        {"stroke", Type::Num, false, false, "stroke thickness in world units", {1}},
        {"color", Type::Color, false, false, "ink colour (black)", {0, 0, 0, 1}},
        {"opacity", Type::Num, false, false, "0..1", {1}},
        {"origin", Type::Vec2, false, false, "where the family's (0, 0) sits", {0, 0}},
        {"rotation", Type::Angle, false, false, "turn of the family about its origin", {0}},
        {"offset",
         Type::Vec2,
         false,
         false,
         "walking families: member n is moved by n * offset (turned with it)",
         {0, 0}},
        {"turn",
         Type::Angle,
         false,
         false,
         "walking families: member n is turned by n * turn",
         {0}},
        {"field", Type::Num, false, false,
         "a scalar field encoded into the phase: the fringes against a twin are its contours"},
        {"gain",
         Type::Num,
         false,
         false,
         "how strongly the field is encoded: contours every 1 / gain",
         {1}},
        {"morph_time",
         Type::Num,
         false,
         false,
         "morphs: seconds each change of family takes (eased, cubic)",
         {0.28}},
    };
    return props;
}

// The checks read these names (Sema.cpp: checkTiming, checkFamily); what each one may depend
// on is checked there, so only the name, type and meaning are listed.
const std::vector<PropertySpec>& timingProperties() {
    static const std::vector<PropertySpec> props = {
        {"period", Type::Num, true, true, "seconds one pass from 0 to 1 takes"},
        {"delay", Type::Num, true, true, "seconds before the first pass starts", {0}},
        {"mode", Type::Error, true, true,
         "what follows a pass: once (held at 1), loop (again from 0) or pingpong (back to 0)"},
        {"easing", Type::Error, true, true,
         "the easing that shapes each pass, by name (default: linear)"},
    };
    return props;
}

const std::vector<PropertySpec>& familyProperties() {
    static const std::vector<PropertySpec> props = {
        {"phase", Type::Num, false, false,
         "the phase, in world units: the members are its level sets n * spacing + offset"},
        {"first", Type::Num, true, true, "the lowest member index drawn (a whole number)"},
        {"facets", Type::Num, true, true,
         "the phase is a regular polygon's support function with this many flat sides (0: a "
         "circle), so the members can walk"},
        {"distance", Type::Num, false, false,
         "the distance to the nearest member, for a family that is not one phase"},
        {"index", Type::Num, false, false, "with distance: the index of the nearest member"},
    };
    return props;
}

std::vector<std::string> propertyNames(const std::vector<PropertySpec>& table) {
    std::vector<std::string> names;
    for (const PropertySpec& s : table) names.push_back(s.name);
    return names;
}

const std::vector<std::string>& timingPropertyNames() {
    static const std::vector<std::string> names = propertyNames(timingProperties());
    return names;
}

const std::vector<std::string>& familyBodyPropertyNames() {
    static const std::vector<std::string> names = propertyNames(familyProperties());
    return names;
}

const std::vector<std::string>& timingModeNames() {
    static const std::vector<std::string> names = {"once", "loop", "pingpong"};
    return names;
}

const PropertySpec& propertySpec(const std::vector<PropertySpec>& table, std::string_view name) {
    for (const PropertySpec& s : table)
        if (name == s.name) return s;
    MOIRE_ICE("no property named '{}' in the table", name);
}

} // namespace moire::sema
