// A two-layer scene compiled with its layers' fields as outputs and run on the JIT over a
// frame, at one sample per pixel or at k x k evenly spaced sub-samples of every pixel (the
// same frame rendered k times larger, never held whole: it streams in bands of k rows).
// The stroke floor of §8.2 and the comparison with explicit geometry of §9.5 read both.
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/Compile.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace moire::exp {

// One layer's fields at a sample (what the kernel outputs with CompileOptions::layerFields).
struct FieldsAt {
    double index, distance, gx, gy;
};

// The k x k sub-samples of one pixel: sample (i, j), i across and j down, lies at the
// pixel's corner plus ((i + 0.5) / k, (j + 0.5) / k) pixels.
class PixelSamples {
  public:
    PixelSamples(const float* rows, size_t stride, int outputs, int k, int x)
        : rows_(rows), stride_(stride), n_(outputs), k_(k), x_(x) {}
    int k() const { return k_; }
    FieldsAt layer(int i, int j, int l) const {
        const float* o = rows_ + size_t(j) * stride_ + size_t(x_ * k_ + i) * n_ + 4 + 6 * l;
        return {o[0], o[1], o[2], o[3]};
    }
    // The kernel's composited colour (RGBA) at the sample.
    const float* rgba(int i, int j) const {
        return rows_ + size_t(j) * stride_ + size_t(x_ * k_ + i) * n_;
    }

  private:
    const float* rows_;
    size_t stride_;
    int n_, k_, x_;
};

class SceneRaster {
  public:
    // Compiles `text`, point-sampled, with the layers' fields as outputs (floored: the
    // renderer's stroke floor on or off, CompileOptions::strokeFloor). A scene with an error,
    // or with other than two layers, prints its diagnostics and exits with status 2.
    SceneRaster(const std::string& name, const std::string& text, bool floored = true);
    ~SceneRaster();

    // The world size of one pixel of a width x height image of the scene's frame.
    double pixelSize(int width, int height) const;

    // Calls visit(x, y, samples) for every pixel of a width x height image, with its k x k
    // sub-samples; from several threads at once, each pixel once.
    using Visit = std::function<void(int x, int y, const PixelSamples& samples)>;
    void sample(int width, int height, int k, const Visit& visit) const;

  private:
    std::unique_ptr<SceneProgram> program_;
    std::unique_ptr<Backend> jit_;
    std::unique_ptr<CompiledKernel> kernel_;
};

} // namespace moire::exp
