#include "runtime/output/PngBands.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <zlib.h>

namespace moire {

namespace {

constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
// A chunk's length is below 2^31; pixel data longer than this goes in several IDAT chunks.
constexpr size_t kMaxChunk = size_t{1} << 30;

void put32(std::vector<unsigned char>& out, uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8)
        out.push_back(static_cast<unsigned char>(v >> shift));
}

uint32_t get32(const unsigned char* p) {
    return uint32_t{p[0]} << 24 | uint32_t{p[1]} << 16 | uint32_t{p[2]} << 8 | p[3];
}

// One chunk: length, type, data, CRC.
void putChunk(std::vector<unsigned char>& out, const char* type, const unsigned char* data,
              size_t size) {
    put32(out, static_cast<uint32_t>(size));
    uLong crc = crc32(0, reinterpret_cast<const Bytef*>(type), 4);
    if (size > 0) crc = crc32(crc, data, static_cast<uInt>(size));
    out.insert(out.end(), type, type + 4);
    if (size > 0) out.insert(out.end(), data, data + size);
    put32(out, static_cast<uint32_t>(crc));
}

enum Filter : unsigned char { None = 0, Sub = 1, Up = 2, Average = 3, Paeth = 4 };

// The Paeth predictor of the PNG specification, written without branches (so that the loops
// below vectorise): p = a + b - c, and the one of a, b, c nearest p, ties in that order.
inline int paeth(int a, int b, int c) {
    const int pa = std::abs(b - c), pb = std::abs(a - c), pc = std::abs(a + b - 2 * c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

// A filtered byte read as a signed difference, its size: the heuristic's measure.
inline uint32_t mag(int d) {
    return static_cast<uint32_t>(std::abs(static_cast<signed char>(d)));
}

// Writes the filter type byte and row `cur` filtered (n + 1 bytes) to `out`, choosing the
// filter by the PNG specification's heuristic: the smallest sum of the filtered bytes read as
// signed differences. `prev` is the row above, or null where it may not be used (the first
// row of a band): then only None and Sub are tried. The first pixel (bpp bytes) has no left
// neighbour: a and c are 0 there. Sums fit 32 bits (a row is under 2^20 bytes).
void filterRow(const unsigned char* cur, const unsigned char* prev, size_t n, size_t bpp,
               unsigned char* out) {
    uint32_t none = 0, sub = 0, up = 0, pae = 0;
    for (size_t i = 0; i < n; ++i) none += mag(cur[i]);
    for (size_t i = 0; i < bpp; ++i) sub += mag(cur[i]);
    for (size_t i = bpp; i < n; ++i) sub += mag(cur[i] - cur[i - bpp]);
    if (prev) {
        for (size_t i = 0; i < n; ++i) up += mag(cur[i] - prev[i]);
        for (size_t i = 0; i < bpp; ++i) pae += mag(cur[i] - prev[i]); // Paeth(0, b, 0) = b
        for (size_t i = bpp; i < n; ++i)
            pae += mag(cur[i] - paeth(cur[i - bpp], prev[i], prev[i - bpp]));
    }
    Filter f = sub < none ? Sub : None;
    uint32_t best = std::min(sub, none);
    if (prev && up < best) f = Up, best = up;
    if (prev && pae < best) f = Paeth;
    out[0] = f;
    unsigned char* o = out + 1;
    switch (f) {
    case Sub:
        std::memcpy(o, cur, bpp);
        for (size_t i = bpp; i < n; ++i) o[i] = static_cast<unsigned char>(cur[i] - cur[i - bpp]);
        break;
    case Up:
        for (size_t i = 0; i < n; ++i) o[i] = static_cast<unsigned char>(cur[i] - prev[i]);
        break;
    case Paeth:
        for (size_t i = 0; i < bpp; ++i) o[i] = static_cast<unsigned char>(cur[i] - prev[i]);
        for (size_t i = bpp; i < n; ++i)
            o[i] = static_cast<unsigned char>(cur[i] - paeth(cur[i - bpp], prev[i], prev[i - bpp]));
        break;
    default:
        std::memcpy(o, cur, n);
        break;
    }
}

// x rounded to the nearest integer, halves away from zero, for 0 <= x < 2^23: std::round
// without a call per value, in a form the compiler vectorises. x - trunc(x) is exact.
inline uint32_t roundHalfAway(float x) {
    const int t = static_cast<int>(x);
    return static_cast<uint32_t>(t) + (x - static_cast<float>(t) >= 0.5f ? 1u : 0u);
}

// v clamped to [0, 1] (NaN to 0), scaled and rounded.
inline uint32_t quantize(float v, float scale) {
    v = v > 0.0f ? v : 0.0f;
    v = v < 1.0f ? v : 1.0f;
    return roundHalfAway(v * scale);
}

} // namespace

void quantizeRow(const float* src, int width, int channels, int bits, unsigned char* out) {
    const size_t count = static_cast<size_t>(width) * 4;
    // RGBA alone in the frame (the common case) is one run of floats: a loop that vectorises.
    if (channels == 4 && bits == 8) {
        for (size_t i = 0; i < count; ++i)
            out[i] = static_cast<unsigned char>(quantize(src[i], 255.0f));
        return;
    }
    for (size_t i = 0; i < count; ++i) {
        const uint32_t q = quantize(src[i / 4 * channels + i % 4], bits == 8 ? 255.0f : 65535.0f);
        if (bits == 8) {
            out[i] = static_cast<unsigned char>(q);
        } else { // big-endian
            out[2 * i] = static_cast<unsigned char>(q >> 8);
            out[2 * i + 1] = static_cast<unsigned char>(q);
        }
    }
}

PngBands::PngBands(int width, int height, int bits, int level, int bandRows)
    : width_(width), height_(height), bits_(bits), level_(std::clamp(level, 0, 9)),
      bandRows_(std::max(1, bandRows)),
      bands_(static_cast<size_t>((height + bandRows_ - 1) / bandRows_)) {
    if (width < 1 || height < 1 || (bits != 8 && bits != 16))
        throw std::invalid_argument("PngBands: bad image shape");
}

int PngBands::rowsIn(int band) const {
    return std::min(bandRows_, height_ - firstRow(band));
}

namespace {

// A thread's working memory for its bands, kept from one band to the next: a frame's bands
// come on the same few threads, and fresh buffers for each (with zlib's own state, about
// 256 KiB at level 4) cost a page fault for every 4 KiB touched and a zero-fill the encoder
// then overwrites; they were a fifth of a 1080p render's time.
class Scratch {
  public:
    ~Scratch() {
        if (level_ >= 0) deflateEnd(&z_);
    }
    // Room for `n` bytes, contents not kept.
    unsigned char* filtered(size_t n) { return reserve(filtered_, filteredSize_, n); }
    unsigned char* raw(int which, size_t n) { return reserve(raw_[which], rawSize_[which], n); }
    // The deflate output: room for `n` bytes; grow() doubles it, keeping what was written.
    unsigned char* deflated(size_t n) { return reserve(deflated_, deflatedSize_, n); }
    unsigned char* grow() {
        auto bigger = std::make_unique_for_overwrite<unsigned char[]>(2 * deflatedSize_);
        std::memcpy(bigger.get(), deflated_.get(), deflatedSize_);
        deflated_ = std::move(bigger);
        deflatedSize_ *= 2;
        return deflated_.get();
    }
    size_t deflatedSize() const { return deflatedSize_; }
    // A raw deflate stream at `level`, fresh (reset when it was used before).
    z_stream& stream(int level) {
        if (level_ != level) {
            if (level_ >= 0) deflateEnd(&z_);
            z_ = z_stream{};
            level_ = -1;
            if (deflateInit2(&z_, level, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK)
                throw std::runtime_error("zlib cannot start a deflate stream");
            level_ = level;
        } else if (deflateReset(&z_) != Z_OK) {
            throw std::runtime_error("zlib cannot reset a deflate stream");
        }
        return z_;
    }

  private:
    using Buffer = std::unique_ptr<unsigned char[]>;
    static unsigned char* reserve(Buffer& buffer, size_t& size, size_t n) {
        if (size < n) {
            buffer = std::make_unique_for_overwrite<unsigned char[]>(n);
            size = n;
        }
        return buffer.get();
    }
    Buffer filtered_, raw_[2], deflated_;
    size_t filteredSize_ = 0, rawSize_[2] = {0, 0}, deflatedSize_ = 0;
    z_stream z_{};
    int level_ = -1;
};

thread_local Scratch scratch;

} // namespace

void PngBands::encode(int band, const float* rows, size_t stride, int channels) {
    encodeRows(band, 0, rowsIn(band), rows, stride, channels);
}

bool PngBands::encodeRows(int band, int first, int count, const float* rows, size_t stride,
                          int channels) {
    const int bpp = 4 * bits_ / 8;
    const size_t rowBytes = static_cast<size_t>(width_) * bpp;
    const int total = rowsIn(band);
    if (first < 0 || count < 1 || first + count > total)
        throw std::logic_error("PngBands: rows outside the band");

    // The thread's scratch holds the band's filtered rows so far and its last raw row (the
    // Up and Paeth filters read the row above) from one call to the next.
    unsigned char* raw[2] = {scratch.raw(0, rowBytes), scratch.raw(1, rowBytes)};
    const size_t filteredSize = static_cast<size_t>(total) * (rowBytes + 1);
    unsigned char* filtered = scratch.filtered(filteredSize);
    for (int r = first; r < first + count; ++r) {
        unsigned char* cur = raw[r % 2];
        quantizeRow(rows + static_cast<size_t>(r - first) * stride, width_, channels, bits_, cur);
        filterRow(cur, r > 0 ? raw[(r + 1) % 2] : nullptr, rowBytes, static_cast<size_t>(bpp),
                  filtered + static_cast<size_t>(r) * (rowBytes + 1));
    }
    if (first + count < total) return false;

    Band& b = bands_[static_cast<size_t>(band)];
    b.adler = static_cast<uint32_t>(adler32(1, filtered, static_cast<uInt>(filteredSize)));
    z_stream& z = scratch.stream(level_);
    const bool lastBand = band + 1 == bands();
    const int flush = lastBand ? Z_FINISH : Z_SYNC_FLUSH;
    // Room for the whole band in one call; a sync flush adds an empty stored block.
    unsigned char* out = scratch.deflated(deflateBound(&z, static_cast<uLong>(filteredSize)) + 64);
    z.next_in = filtered;
    z.avail_in = static_cast<uInt>(filteredSize);
    size_t used = 0;
    int status = Z_OK;
    do {
        if (used == scratch.deflatedSize()) out = scratch.grow();
        z.next_out = out + used;
        z.avail_out = static_cast<uInt>(scratch.deflatedSize() - used);
        status = deflate(&z, flush);
        used = scratch.deflatedSize() - z.avail_out;
    } while (status == Z_OK && (lastBand || z.avail_in > 0 || z.avail_out == 0));
    if (status != (lastBand ? Z_STREAM_END : Z_OK) && !(status == Z_BUF_ERROR && !lastBand))
        throw std::runtime_error("zlib failed to compress the image");
    b.deflated.assign(out, out + used);
    b.done = true;
    return true;
}

std::vector<unsigned char> PngBands::head(const std::vector<unsigned char>& chunks) const {
    std::vector<unsigned char> out(std::begin(kSignature), std::end(kSignature));
    std::vector<unsigned char> ihdr;
    put32(ihdr, static_cast<uint32_t>(width_));
    put32(ihdr, static_cast<uint32_t>(height_));
    // bit depth, colour type 6 (RGBA), deflate, adaptive filtering, no interlace
    for (unsigned char v : {static_cast<unsigned char>(bits_), (unsigned char)6, (unsigned char)0,
                            (unsigned char)0, (unsigned char)0})
        ihdr.push_back(v);
    putChunk(out, "IHDR", ihdr.data(), ihdr.size());
    out.insert(out.end(), chunks.begin(), chunks.end());
    // The zlib header: deflate with a 32 KiB window, the level class, and the check bits
    // that make the two bytes a multiple of 31.
    const unsigned cmf = 0x78;
    unsigned flg = (level_ < 2 ? 0u : level_ < 6 ? 1u : level_ == 6 ? 2u : 3u) << 6;
    flg += 31 - (cmf * 256 + flg) % 31;
    const unsigned char header[2] = {static_cast<unsigned char>(cmf),
                                     static_cast<unsigned char>(flg)};
    putChunk(out, "IDAT", header, 2);
    return out;
}

std::vector<unsigned char> PngBands::bandData(int band) const {
    const Band& b = bands_.at(static_cast<size_t>(band));
    if (!b.done) throw std::logic_error("PngBands: a band was not encoded");
    std::vector<unsigned char> out;
    out.reserve(b.deflated.size() + 12 * (1 + b.deflated.size() / kMaxChunk));
    for (size_t at = 0; at < b.deflated.size(); at += kMaxChunk)
        putChunk(out, "IDAT", b.deflated.data() + at, std::min(kMaxChunk, b.deflated.size() - at));
    return out;
}

std::vector<unsigned char> PngBands::tail() const {
    uint32_t adler = 1;
    for (size_t i = 0; i < bands_.size(); ++i) {
        if (!bands_[i].done) throw std::logic_error("PngBands: a band was not encoded");
        const size_t length =
            static_cast<size_t>(rowsIn(static_cast<int>(i))) * (1 + size_t(width_) * 4 * bits_ / 8);
        adler = static_cast<uint32_t>(
            adler32_combine(adler, bands_[i].adler, static_cast<z_off_t>(length)));
    }
    std::vector<unsigned char> trailer, out;
    put32(trailer, adler);
    putChunk(out, "IDAT", trailer.data(), trailer.size());
    putChunk(out, "IEND", nullptr, 0);
    return out;
}

void PngBands::release(int band) {
    std::vector<unsigned char>().swap(bands_.at(static_cast<size_t>(band)).deflated);
}

std::vector<unsigned char> PngBands::file(const std::vector<unsigned char>& chunks) const {
    std::vector<unsigned char> out = head(chunks);
    size_t size = out.size() + 24;
    for (const Band& b : bands_)
        size += b.deflated.size() + 12 * (1 + b.deflated.size() / kMaxChunk);
    out.reserve(size);
    for (int i = 0; i < bands(); ++i) {
        std::vector<unsigned char> data = bandData(i);
        out.insert(out.end(), data.begin(), data.end());
    }
    std::vector<unsigned char> end = tail();
    out.insert(out.end(), end.begin(), end.end());
    return out;
}

std::vector<unsigned char> pngColourChunks(double dpi, const std::string& software,
                                           const PngPlacement& placement) {
    std::vector<unsigned char> out;
    auto chunk = [&](const char* type, const std::vector<unsigned char>& data) {
        putChunk(out, type, data.data(), data.size());
    };
    auto be32 = [](std::initializer_list<uint32_t> values) {
        std::vector<unsigned char> data;
        for (uint32_t v : values) put32(data, v);
        return data;
    };
    // sRGB with its fallbacks for readers that ignore the sRGB chunk: gamma 1/2.2 and the
    // sRGB primaries and white point, as the PNG specification recommends (values x 100000).
    chunk("gAMA", be32({45455}));
    chunk("sRGB", {3}); // rendering intent: absolute colorimetric, as OpenImageIO writes it
    chunk("cHRM", be32({31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000}));
    // The offset: two signed 32-bit numbers and the unit, 0 for pixels.
    std::vector<unsigned char> offset =
        be32({static_cast<uint32_t>(placement.x), static_cast<uint32_t>(placement.y)});
    offset.push_back(0);
    chunk("oFFs", offset);
    if (dpi > 0) {
        // Pixels per metre, truncated as OpenImageIO converts dots per inch.
        const uint32_t perMetre = pngPixelsPerMetre(dpi);
        std::vector<unsigned char> phys = be32({perMetre, perMetre});
        phys.push_back(1); // the unit is the metre
        chunk("pHYs", phys);
    }
    auto text = [&](const std::string& key, const std::string& value) {
        std::vector<unsigned char> data(key.begin(), key.end());
        data.push_back(0);
        data.insert(data.end(), value.begin(), value.end());
        chunk("tEXt", data);
    };
    text("oiio:ColorSpace", "sRGB");
    text("Software", software);
    if (placement.fullWidth > 0)
        text(kPngFullSizeKey,
             std::to_string(placement.fullWidth) + "x" + std::to_string(placement.fullHeight));
    return out;
}

std::vector<unsigned char> pngChunksBeforeData(const std::vector<unsigned char>& png) {
    if (png.size() < sizeof kSignature ||
        !std::equal(std::begin(kSignature), std::end(kSignature), png.begin()))
        throw std::runtime_error("not a PNG file");
    std::vector<unsigned char> chunks;
    for (size_t at = sizeof kSignature; at + 12 <= png.size();) {
        const size_t whole = 12 + size_t{get32(png.data() + at)};
        if (at + whole > png.size()) throw std::runtime_error("a PNG chunk runs past the file");
        const unsigned char* type = png.data() + at + 4;
        if (std::memcmp(type, "IDAT", 4) == 0 || std::memcmp(type, "IEND", 4) == 0) break;
        if (std::memcmp(type, "IHDR", 4) != 0)
            chunks.insert(chunks.end(), png.begin() + static_cast<std::ptrdiff_t>(at),
                          png.begin() + static_cast<std::ptrdiff_t>(at + whole));
        at += whole;
    }
    return chunks;
}

} // namespace moire
