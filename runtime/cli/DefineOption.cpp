#include "runtime/cli/DefineOption.h"

#include "compiler/diag/Diagnostics.h"

#include <cctype>

namespace moire::cli {

void addDefineOption(CLI::App* cmd, std::vector<std::string>& raw) {
    cmd->add_option("-D,--define", raw,
                    "Set a param (NAME=VALUE) or a named layer's property (LAYER.PROPERTY=VALUE), "
                    "the value written as in the scene; repeatable")
        ->allow_extra_args(false)
        ->take_all();
}

namespace {
bool isName(std::string_view s) {
    if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
    for (char c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
    return true;
}

// NAME or LAYER.PROPERTY.
bool isTarget(std::string_view s) {
    size_t dot = s.find('.');
    if (dot == std::string_view::npos) return isName(s);
    return isName(s.substr(0, dot)) && isName(s.substr(dot + 1));
}
} // namespace

bool collectDefines(int argc, const char* const* argv, Defines& out, std::string& diagnostics) {
    // The command line as diagnostics show it: `moire` and the arguments, joined by spaces.
    std::string line = "moire";
    std::vector<size_t> at(static_cast<size_t>(argc), 0);
    for (int i = 1; i < argc; ++i) {
        line += ' ';
        at[static_cast<size_t>(i)] = line.size();
        line += argv[i];
    }
    out.commandLine = line;
    out.list.clear();
    SourceManager sm;
    const uint32_t file = sm.add("<command line>", line);
    DiagEngine diags(sm);
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        if (arg == "--") break;
        std::string_view text;
        size_t offset = 0;
        if ((arg == "-D" || arg == "--define") && i + 1 < argc) {
            ++i;
            text = argv[i];
            offset = at[static_cast<size_t>(i)];
        } else if (arg.starts_with("--define=")) {
            text = arg.substr(9);
            offset = at[static_cast<size_t>(i)] + 9;
        } else if (arg.starts_with("-D") && arg.size() > 2) {
            text = arg.substr(2);
            offset = at[static_cast<size_t>(i)] + 2;
        } else {
            continue;
        }
        const size_t eq = text.find('=');
        if (eq == std::string_view::npos || !isTarget(text.substr(0, eq)) ||
            text.find_first_not_of(" \t", eq + 1) == std::string_view::npos) {
            SourceRange r;
            r.begin = {file, static_cast<uint32_t>(offset)};
            r.length = static_cast<uint32_t>(std::max<size_t>(text.size(), 1));
            diags.error(r, Msg::DefineSyntax, std::string(text));
            continue;
        }
        Define d;
        d.target = std::string(text.substr(0, eq));
        d.value = std::string(text.substr(eq + 1));
        d.targetOffset = offset;
        d.valueOffset = offset + eq + 1;
        out.list.push_back(std::move(d));
    }
    diagnostics = diags.render();
    return !diags.hasErrors();
}

} // namespace moire::cli
