// `moire names`: every name the language knows, grouped by kind (compiler/LanguageNames.h),
// as text or as JSON for tools. The editor packages' highlighting is generated from the JSON
// (scripts/gen-editor-names.mjs).
#include "compiler/LanguageNames.h"
#include "runtime/cli/Commands.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

namespace moire::cli {

namespace {

nlohmann::ordered_json asJson(const LanguageNames& n) {
    nlohmann::ordered_json j;
    j["keywords"] = n.keywords;
    nlohmann::ordered_json blocks = nlohmann::ordered_json::object();
    for (const BlockNames& b : n.blocks) blocks[b.kind] = b.properties;
    j["blocks"] = blocks;
    j["properties"] = n.properties;
    nlohmann::ordered_json families = nlohmann::ordered_json::array();
    for (const FamilyNames& f : n.families)
        families.push_back({{"name", f.name}, {"params", f.params}, {"builtin", f.builtin}});
    j["families"] = families;
    j["functions"] = n.functions;
    j["fields"] = n.fields;
    j["easings"] = n.easings;
    j["constants"] = n.constants;
    j["variables"] = n.variables;
    j["words"] = n.words;
    j["units"] = n.units;
    return j;
}

} // namespace

int names(const NamesArgs& args) {
    const LanguageNames n = languageNames();
    if (args.verbosity.verbose)
        fmt::print(stderr,
                   "moire: {} keywords, {} properties, {} families, {} functions, {} fields, {} "
                   "easings, {} constants, {} variables, {} words, {} units\n",
                   n.keywords.size(), n.properties.size(), n.families.size(), n.functions.size(),
                   n.fields.size(), n.easings.size(), n.constants.size(), n.variables.size(),
                   n.words.size(), n.units.size());
    if (args.json) {
        fmt::print("{}\n", asJson(n).dump(2));
        return kExitOk;
    }
    auto line = [](const char* kind, const std::vector<std::string>& names) {
        fmt::print("{}: {}\n", kind, fmt::join(names, " "));
    };
    line("keywords", n.keywords);
    for (const BlockNames& b : n.blocks)
        line(fmt::format("{} properties", b.kind).c_str(), b.properties);
    std::vector<std::string> families;
    for (const FamilyNames& f : n.families)
        families.push_back(
            f.params.empty() ? f.name : fmt::format("{}({})", f.name, fmt::join(f.params, ", ")));
    fmt::print("families: {}\n", fmt::join(families, " "));
    line("functions", n.functions);
    line("fields", n.fields);
    line("easings", n.easings);
    line("constants", n.constants);
    line("variables", n.variables);
    line("words", n.words);
    line("units", n.units);
    return kExitOk;
}

} // namespace moire::cli
