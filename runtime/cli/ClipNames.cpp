#include "runtime/cli/ClipNames.h"

#include <cctype>
#include <charconv>
#include <fmt/format.h>

namespace moire::cli {

std::optional<FrameRange> parseFrames(const std::string& text, std::string& error) {
    // Frame numbers stay far below 2^53, where n / fps would stop being exact.
    constexpr int64_t kMaxFrame = 999'999'999'999;
    auto number = [](std::string_view s, int64_t& v) {
        auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        return ec == std::errc() && end == s.data() + s.size() && !s.empty() && v >= 0 &&
               v <= kMaxFrame;
    };
    std::string_view s = text;
    FrameRange r;
    size_t dots = s.find("..");
    bool ok;
    if (dots == std::string_view::npos) {
        int64_t n = 0;
        ok = number(s, n) && n >= 1;
        r = {0, n - 1};
    } else {
        ok = number(s.substr(0, dots), r.first) && number(s.substr(dots + 2), r.last) &&
             r.first <= r.last;
    }
    if (!ok) {
        error = fmt::format("--frames must be a count N (frames 0 to N-1) or a range A..B of "
                            "frame numbers (A <= B, both included, at most {}), not '{}'",
                            kMaxFrame, text);
        return std::nullopt;
    }
    return r;
}

std::string NamePattern::name(int64_t frame) const {
    if (!numbered) return before;
    return before +
           (zeroPad ? fmt::format("{:0{}d}", frame, width) : fmt::format("{:{}d}", frame, width)) +
           after;
}

std::optional<NamePattern> parseNamePattern(const std::string& path, std::string& error) {
    NamePattern p;
    // Only the file name is a pattern: a '%' in a directory is part of its name.
    size_t slash = path.rfind('/');
    size_t start = slash == std::string::npos ? 0 : slash + 1;
    p.before = path.substr(0, start);
    std::string* part = &p.before;
    for (size_t i = start; i < path.size(); ++i) {
        if (path[i] != '%') {
            *part += path[i];
            continue;
        }
        size_t j = i + 1;
        if (j < path.size() && path[j] == '%') {
            *part += '%';
            i = j;
            continue;
        }
        bool zero = j < path.size() && path[j] == '0';
        if (zero) ++j;
        int width = 0;
        while (j < path.size() && std::isdigit(static_cast<unsigned char>(path[j])) && width < 100)
            width = width * 10 + (path[j++] - '0');
        if (j >= path.size() || path[j] != 'd' || width > 18) {
            error = fmt::format("the output name '{}' has a '%' that is not a frame number: use "
                                "%d or %04d (width and zero padding allowed), or %% for a "
                                "percent sign",
                                path);
            return std::nullopt;
        }
        if (p.numbered) {
            error = fmt::format("the output name '{}' has more than one frame number", path);
            return std::nullopt;
        }
        p.numbered = true;
        p.zeroPad = zero;
        p.width = width;
        part = &p.after;
        i = j;
    }
    return p;
}

} // namespace moire::cli
