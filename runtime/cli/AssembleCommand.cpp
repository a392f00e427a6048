// `moire assemble`: region tiles (render --region) joined into the whole frame, band by band,
// so that no more than a band of the frame and a band of each tile it crosses is ever in
// memory. The tiles' placements say where each goes; they must cover the frame exactly once.
// The whole goes through the same writer (ImageStream.h), with the same depth and resolution,
// as `render` writes a whole frame, so that the tiles of a frame assemble into the very file a
// render of the whole would have made.
#include "runtime/cli/Commands.h"
#include "runtime/cli/Shared.h"
#include "runtime/cli/StopSignals.h"
#include "runtime/cli/TileLayout.h"
#include "runtime/FrameEval.h"
#include "runtime/output/ImageIO.h"
#include "runtime/output/ImageStream.h"
#include "runtime/output/OiioCodec.h"
#include "runtime/output/OutputFile.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <memory>
#include <vector>

namespace moire::cli {

namespace {

namespace fs = std::filesystem;

// Rows a band of the whole holds: 64, fewer for a frame so wide that 64 rows of floats would
// pass 64 MiB.
int bandRowsFor(int width) {
    const int64_t rowBytes = int64_t{width} * 4 * static_cast<int64_t>(sizeof(float));
    return static_cast<int>(std::clamp<int64_t>((int64_t{64} << 20) / rowBytes, 1, 64));
}

const char* depthName(PixelDepth d) {
    switch (d) {
    case PixelDepth::U8:
        return "8-bit";
    case PixelDepth::U16:
        return "16-bit";
    case PixelDepth::Half:
        return "half-float";
    default:
        return "float";
    }
}

struct Tile {
    std::string path;
    ImageFileInfo info;
    std::unique_ptr<ImageRowReader> reader; // open while the bands cross it
};

// Opens a tile to read its placement, or says why it cannot be read.
std::unique_ptr<ImageRowReader> openTile(const std::string& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw IoError(fmt::format("cannot read '{}': no such file", path));
    if (imageFormatOf(path).empty() || imageFormatOf(path) == "jpeg")
        throw IoError(fmt::format("cannot read '{}' as a tile: tiles are .png, .tif or .exr "
                                  "files written by render --region",
                                  path));
    return oiioCodec().openRows(path);
}

// Why the tiles cannot make one frame: different frames, channels, depths or resolutions,
// naming the first tile that differs from the first; "" when they agree.
std::string mismatch(const std::vector<Tile>& tiles) {
    const Tile& a = tiles.front();
    for (const Tile& b : tiles) {
        const ImageFileInfo &i = a.info, &j = b.info;
        if (j.fullWidth != i.fullWidth || j.fullHeight != i.fullHeight)
            return fmt::format("'{}' is a region of a {}x{} frame, '{}' of a {}x{} frame", a.path,
                               i.fullWidth, i.fullHeight, b.path, j.fullWidth, j.fullHeight);
        if (j.channels != i.channels)
            return fmt::format("'{}' has {} channels, '{}' {}", a.path, i.channels, b.path,
                               j.channels);
        if (j.depth != i.depth || j.linear != i.linear)
            return fmt::format("'{}' holds {}{} samples, '{}' {}{}", a.path, depthName(i.depth),
                               i.linear ? " linear" : "", b.path, depthName(j.depth),
                               j.linear ? " linear" : "");
        if (j.dpi != i.dpi)
            return fmt::format("'{}' records {:g} dpi, '{}' {:g}", a.path, i.dpi, b.path, j.dpi);
    }
    return "";
}

} // namespace

int assemble(const AssembleArgs& args) {
    const auto t0 = std::chrono::steady_clock::now();
    Stages stages(args.verbosity);
    const std::string format = imageFormatOf(args.output);
    if (format.empty()) {
        fmt::print(
            stderr,
            "moire: error: cannot write '{}': unknown image format; use .png, .tif, .exr or .jpg\n",
            args.output);
        return kExitUsage;
    }
    int sizeW = 0, sizeH = 0;
    if (!args.size.empty() && !parseSize(args.size, sizeW, sizeH)) {
        fmt::print(stderr,
                   "moire: error: --size must be WIDTHxHEIGHT in pixels (1 to {}), not '{}'\n",
                   kMaxImageSide, args.size);
        return kExitUsage;
    }
    PixelDepth depth = PixelDepth::Default;
    if (!parseDepth(args.depth, depth)) {
        fmt::print(stderr, "moire: error: --depth must be 8, 16, half or float, not '{}'\n",
                   args.depth);
        return kExitUsage;
    }
    if (std::string problem = depthProblem(format, depth); !problem.empty()) {
        fmt::print(stderr, "moire: error: cannot write '{}': {}\n", args.output, problem);
        return kExitUsage;
    }
    if (args.compression != -1 &&
        (args.compression < 0 || args.compression > 9 || format != "png")) {
        fmt::print(stderr,
                   "moire: error: --compression sets a PNG's zlib level, from 0 (none) to 9 "
                   "(smallest); not {} for '{}'\n",
                   args.compression, args.output);
        return kExitUsage;
    }

    // Every tile's placement, read from its header (the pixels wait for their bands).
    std::vector<Tile> tiles;
    try {
        for (const std::string& path : args.tiles) {
            Tile t{path, {}, openTile(path)};
            t.info = t.reader->info();
            t.reader.reset(); // a poster may have more tiles than a process may open files
            tiles.push_back(std::move(t));
        }
    } catch (const IoError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    if (std::string why = mismatch(tiles); !why.empty()) {
        fmt::print(stderr, "moire: error: the tiles are not of one frame: {}\n", why);
        return kExitUsage;
    }
    const ImageFileInfo& first = tiles.front().info;
    const int width = first.fullWidth, height = first.fullHeight;
    if (sizeW && (sizeW != width || sizeH != height)) {
        fmt::print(stderr, "moire: error: the tiles make a {}x{} frame, not the {}x{} of --size\n",
                   width, height, sizeW, sizeH);
        return kExitUsage;
    }
    if (std::string problem = sizeProblem(format, width, height); !problem.empty()) {
        fmt::print(stderr, "moire: error: cannot write '{}': {}\n", args.output, problem);
        return kExitUsage;
    }
    std::vector<PlacedTile> placed;
    for (const Tile& t : tiles)
        placed.push_back({t.path, t.info.x, t.info.y, t.info.width, t.info.height});
    if (std::string why = coverProblem(placed, width, height); !why.empty()) {
        fmt::print(stderr, "moire: error: the tiles do not make the frame once: {}\n", why);
        return kExitUsage;
    }
    stages.done(
        fmt::format("read the placements of {} tiles: a {}x{} frame", tiles.size(), width, height));

    // The whole as render would write it: the tiles' depth (or --depth, or the format's own
    // when it cannot hold theirs) and resolution, no placement.
    WriteOptions wo;
    wo.depth = depth != PixelDepth::Default                ? depth
               : depthProblem(format, first.depth).empty() ? first.depth
                                                           : PixelDepth::Default;
    wo.dpi = first.dpi;
    wo.compression = args.compression;
    wo.threads = args.threads;
    // Linear tiles (EXR) are sRGB-encoded for a file of sRGB samples; an EXR takes them as
    // they are.
    const bool toSrgb = first.linear && format != "exr";
    wo.linearRows = first.linear && format == "exr";

    StopSignals signals;
    try {
        prepareOutputDirectory(args.output);
        removeStaleTemporaries(args.output);
        std::unique_ptr<ImageStream> out = openImageStream(args.output, format, width, height, wo);
        // Steps of rows that never cross one of the writer's bands (a PNG's are encoded apart).
        const int streamBand = std::max(1, out->bandRows());
        const int step = std::min(streamBand, bandRowsFor(width));
        const size_t stride = static_cast<size_t>(width) * 4;
        std::vector<float> band(stride * static_cast<size_t>(step));
        for (int y0 = 0, y1; y0 < height; y0 = y1) {
            if (StopSignals::received()) {
                fmt::print(stderr, "moire: interrupted: {} was not written\n", args.output);
                return 128 + StopSignals::received();
            }
            y1 = std::min({height, y0 + step, (y0 / streamBand + 1) * streamBand});
            for (int i : tilesCrossing(placed, y0, y1)) {
                Tile& t = tiles[static_cast<size_t>(i)];
                if (!t.reader) t.reader = openTile(t.path);
                const int from = std::max(y0, t.info.y),
                          to = std::min(y1, t.info.y + t.info.height);
                float* at = band.data() + static_cast<size_t>(from - y0) * stride +
                            static_cast<size_t>(t.info.x) * 4;
                t.reader->readRows(from - t.info.y, to - from, at, stride);
                if (toSrgb)
                    for (int y = from; y < to; ++y) {
                        float* p = band.data() + static_cast<size_t>(y - y0) * stride +
                                   static_cast<size_t>(t.info.x) * 4;
                        for (int k = 0; k < t.info.width * 4; ++k)
                            if (k % 4 != 3) p[k] = linearToSrgb(std::clamp(p[k], 0.0f, 1.0f));
                    }
                if (to == t.info.y + t.info.height) t.reader.reset(); // its last rows
            }
            out->addRows(y0, y1 - y0, band.data(), stride, 4);
        }
        out->finish();
    } catch (const IoError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    stages.done(fmt::format("wrote {}", args.output));
    if (!args.verbosity.quiet)
        fmt::print(stderr, "moire: wrote {} ({}x{} from {} tiles, {:.0f} ms)\n", args.output, width,
                   height, tiles.size(), secondsSince(t0) * 1000.0);
    return kExitOk;
}

} // namespace moire::cli
