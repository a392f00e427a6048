// What `moire clip` reads from its command line: --frames, and the output name with its
// frame number (frame_%04d.png).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace moire::cli {

// The frames of a clip, first to last inclusive, numbered as in the whole clip.
struct FrameRange {
    int64_t first = 0, last = 0;
    int64_t count() const { return last - first + 1; }
};
// --frames: "N" (frames 0 to N - 1) or "A..B" (A to B inclusive). nullopt with `error` set
// when it is neither.
std::optional<FrameRange> parseFrames(const std::string& text, std::string& error);
// An output name with an optional printf-style frame number in its file name: %d, %4d,
// %04d (%% is a literal percent sign).
struct NamePattern {
    std::string before, after;
    bool numbered = false;
    int width = 0;
    bool zeroPad = false;
    std::string name(int64_t frame) const;
};
std::optional<NamePattern> parseNamePattern(const std::string& path, std::string& error);

} // namespace moire::cli
