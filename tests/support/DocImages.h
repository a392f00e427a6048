// Helpers for the tests that hold the documentation's pictures to what moire draws (the
// gallery, the tutorial, the teaser): rendering a scene with the real binary, comparing a
// fresh render with the stored picture, and reading grey levels and ink off an image.
#pragma once

#include "runtime/Image.h"
#include "tests/support/Support.h"

#include <string>

namespace moire::test {

// Runs `moire render -q ARGS -o DIR/NAME.png` from the source root and reads the image back;
// fails the current test (with moire's stderr) when the render does not succeed.
Image renderWithMoire(const std::string& args, const TempDir& dir, const std::string& name);

// A fresh render against the picture stored in the docs: at most 0.5% of the samples off by
// more than 2/255 and a mean difference under 0.5/255 (the golden images' tolerance: room for
// libm differences between machines, none for a change in what is drawn).
void checkSameAsStored(const Image& fresh, const std::string& storedPath);

// The grey level of a pixel, the mean of its three (sRGB) colour channels, 0 black to 1 white.
double grey(const Image& image, int x, int y);

// The mean ink over columns [x0, x1): how much darker than the paper the pixels are, on
// average, as a fraction of the paper's grey (0 bare paper, 1 black). The paper is taken as
// the lightest grey in those columns.
double meanInk(const Image& image, int x0, int x1);

// Pearson's correlation of two equally long series.
double correlation(const std::vector<double>& a, const std::vector<double>& b);

} // namespace moire::test
