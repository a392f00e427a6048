#include "runtime/view/ParamWriteBack.h"

#include <algorithm>

namespace moire::view {

ParamWriteBack writeBackParameters(const std::string& source, uint32_t fileId,
                                   std::span<const Parameter> params, const ParamSet& set) {
    struct Edit {
        size_t at, length;
        std::string text, name;
    };
    std::vector<Edit> edits;
    ParamWriteBack out;
    for (size_t i = 0; i < params.size() && i < set.size(); ++i) {
        if (!set[i]) continue;
        const Parameter& p = params[i];
        const std::string_view now = defaultText(p, source);
        // A scene's parameters are all declared in its own file: a default from elsewhere is
        // the command line's (`-D`), which the file never said.
        if (p.valueRange.begin.file != fileId || now.empty()) {
            out.skipped.push_back(p.name + ": its value comes from -D on the command line");
            continue;
        }
        const std::optional<ParamValue> was = readLiteral(p, now);
        if (!was) {
            out.skipped.push_back(p.name + ": its default is an expression (" + std::string(now) +
                                  "); the file keeps it");
            continue;
        }
        const ParamValue& v = *set[i];
        if (std::equal(v.begin(), v.begin() + p.components, was->begin())) continue;
        edits.push_back(
            {p.valueRange.begin.offset, p.valueRange.length, literalText(p, v), p.name});
    }
    // From the end of the text back, so that each edit's offsets still hold.
    std::sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.at > b.at; });
    out.text = source;
    for (const Edit& e : edits) out.text.replace(e.at, e.length, e.text);
    for (auto e = edits.rbegin(); e != edits.rend(); ++e) out.written.push_back(e->name);
    return out;
}

} // namespace moire::view
