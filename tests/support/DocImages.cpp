#include "tests/support/DocImages.h"

#include "runtime/output/ImageIO.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <filesystem>

namespace moire::test {

Image renderWithMoire(const std::string& args, const TempDir& dir, const std::string& name) {
    const std::string out = dir.file(name + ".png");
    CommandResult r = runMoireInSourceRoot("render -q " + args + " -o '" + out + "'");
    INFO("moire render ", args, ": ", r.err);
    REQUIRE(r.status == 0);
    return readImage(out);
}

void checkSameAsStored(const Image& fresh, const std::string& storedPath) {
    INFO(storedPath);
    REQUIRE_MESSAGE(std::filesystem::exists(storedPath),
                    "no stored picture; draw it with the docs' render script");
    Image stored = readImage(storedPath);
    REQUIRE_MESSAGE((stored.width == fresh.width && stored.height == fresh.height),
                    "the stored picture is ", stored.width, "x", stored.height, ", the render ",
                    fresh.width, "x", fresh.height);
    ImageDiff d = compareImages(stored, fresh, 2.0 / 255.0);
    INFO("stale? max ", d.maxAbs * 255, "/255, mean ", d.meanAbs * 255, "/255, within ",
         d.fractionWithin(), "; draw it again with the docs' render script");
    CHECK(d.fractionWithin() >= 0.995);
    CHECK(d.meanAbs <= 0.5 / 255.0);
}

double grey(const Image& image, int x, int y) {
    return (image.at(x, y, 0) + image.at(x, y, 1) + image.at(x, y, 2)) / 3.0;
}

double meanInk(const Image& image, int x0, int x1) {
    double paper = 0.0, sum = 0.0;
    size_t all = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = x0; x < x1; ++x, ++all) {
            paper = std::max(paper, grey(image, x, y));
            sum += grey(image, x, y);
        }
    return all && paper > 0 ? 1.0 - sum / all / paper : 0.0;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
    REQUIRE(a.size() == b.size());
    const double n = static_cast<double>(a.size());
    double ma = 0, mb = 0;
    for (size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
    ma /= n, mb /= n;
    double sab = 0, saa = 0, sbb = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

} // namespace moire::test
