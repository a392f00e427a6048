#include "runtime/view/Overlay.h"

#include <algorithm>
#include <sstream>

namespace moire::view {

namespace {

// Cuts `line` to what fits in `width` pixels, marking the cut with "...".
std::string fitted(const std::string& line, int width, int scale) {
    if (font::textWidth(line, scale) <= width) return line;
    const int chars = std::max(0, width / (font::kAdvance * scale) - 3);
    return line.substr(0, chars) + "...";
}

} // namespace

std::vector<std::string> errorLines(const std::string& diagnostics, size_t max) {
    // Each diagnostic: a headline at the margin, then its indented source and caret lines.
    std::vector<std::vector<std::string>> groups;
    std::istringstream in(diagnostics);
    for (std::string line; std::getline(in, line);) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty()) continue;
        const bool headline = line[0] != ' ';
        if (headline || groups.empty()) groups.emplace_back();
        groups.back().push_back(line);
    }
    max = std::max<size_t>(max, 2);
    std::vector<std::string> out;
    for (size_t g = 0; g < groups.size(); ++g) {
        const size_t left = groups.size() - g;
        // Room for this group, and for the "(and N more)" line if others follow it.
        const size_t room = max - out.size() - (left > 1 ? 1 : 0);
        if (groups[g].size() > room) {
            if (out.empty()) { // the first diagnostic is shown, as much of it as fits
                out.assign(groups[g].begin(),
                           groups[g].begin() + static_cast<std::ptrdiff_t>(std::min(
                                                   groups[g].size(), max - (left > 1 ? 1 : 0))));
                if (left > 1) out.push_back("(and " + std::to_string(left - 1) + " more)");
            } else {
                out.push_back("(and " + std::to_string(left) + " more)");
            }
            return out;
        }
        out.insert(out.end(), groups[g].begin(), groups[g].end());
    }
    return out;
}

int statusHeight(int scale) {
    return (font::kLineHeight + 2) * scale;
}

void drawOverlay(Canvas& canvas, const OverlayText& text, int scale) {
    scale = std::max(scale, 1);
    const int pad = 3 * scale, line = font::kLineHeight * scale;
    if (!text.status.empty()) {
        const int h = statusHeight(scale);
        const int y = canvas.height - h;
        fillRect(canvas, 0, y, canvas.width, h, {16, 16, 20, 200});
        font::drawText(canvas, pad, y + 2 * scale,
                       fitted(text.status, canvas.width - 2 * pad, scale), scale,
                       {236, 236, 228, 255});
    }
    if (!text.errorLines.empty()) {
        const int h = static_cast<int>(text.errorLines.size()) * line + 2 * pad;
        fillRect(canvas, 0, 0, canvas.width, h, {90, 12, 16, 215});
        int y = pad;
        for (const std::string& l : text.errorLines) {
            font::drawText(canvas, pad, y, fitted(l, canvas.width - 2 * pad, scale), scale,
                           {255, 236, 220, 255});
            y += line;
        }
    }
}

} // namespace moire::view
