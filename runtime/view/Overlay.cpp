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

std::vector<std::string> errorHeadlines(const std::string& diagnostics, size_t max) {
    std::vector<std::string> lines, headlines;
    std::istringstream in(diagnostics);
    for (std::string line; std::getline(in, line);) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty()) continue;
        lines.push_back(line);
        // The quoted source and its caret are indented; a headline starts at the margin.
        if (line[0] != ' ' && (line.find(": error: ") != std::string::npos ||
                               line.find(": warning: ") != std::string::npos ||
                               line.find(": note: ") != std::string::npos))
            headlines.push_back(line);
    }
    std::vector<std::string>& out = headlines.empty() ? lines : headlines;
    if (out.size() > max) {
        const size_t more = out.size() - (max - 1);
        out.resize(max - 1);
        out.push_back("(and " + std::to_string(more) + " more)");
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
