#include "compiler/sema/Views.h"

#include "compiler/diag/Diagnostics.h"

namespace moire::sema {

const std::vector<ViewName>& viewNames() {
    static const std::vector<ViewName> all = {
        {ViewMode::Pattern, "pattern", "the layers' strokes, inked over the paper"},
        {ViewMode::Envelope, "envelope", "the averaged ink: the fringes with the carriers removed"},
        {ViewMode::Split, "split", "the pattern left of a dashed rule, its envelope right"},
        {ViewMode::Ratio, "ratio",
         "the heterodyne ratio: dark where a fringe stands, hued by which beat it is"},
    };
    return all;
}

std::optional<ViewMode> viewNamed(std::string_view name) {
    for (const ViewName& v : viewNames())
        if (name == v.name) return v.mode;
    return std::nullopt;
}

const char* viewName(ViewMode mode) {
    for (const ViewName& v : viewNames())
        if (v.mode == mode) return v.name;
    MOIRE_ICE("a view without a name");
}

std::string viewList() {
    std::string out;
    const auto& all = viewNames();
    for (size_t i = 0; i < all.size(); ++i) {
        if (i > 0) out += i + 1 == all.size() ? " or " : ", ";
        out += all[i].name;
    }
    return out;
}

bool viewSweeps(ViewMode mode) {
    return mode == ViewMode::Envelope || mode == ViewMode::Split;
}

bool viewReadsCharacters(ViewMode mode) {
    return mode == ViewMode::Ratio;
}

std::optional<bool> switchNamed(std::string_view name) {
    if (name == kSwitchNames[1]) return true;
    if (name == kSwitchNames[0]) return false;
    return std::nullopt;
}

std::optional<FilterMode> filterNamed(std::string_view name) {
    if (name == kFilterNames[0]) return FilterMode::Point;
    if (name == kFilterNames[1]) return FilterMode::Mean;
    return std::nullopt;
}

std::string filterList() {
    return std::string(kFilterNames[0]) + " or " + kFilterNames[1];
}

} // namespace moire::sema
