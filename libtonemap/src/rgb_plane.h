// A small RGB float raster for the reduced-resolution stages of bloom.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

namespace dhdr::detail {

struct RgbPlane {
    int width = 0, height = 0;
    std::vector<float> rgb; // interleaved, row-major

    RgbPlane() = default;
    RgbPlane(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0.0f) {}
    float* at(int x, int y) { return &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3]; }
    const float* at(int x, int y) const {
        return &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3];
    }
};

// Area-weighted (box) resampling to a smaller size: each output pixel is the mean of the
// input area it covers, fractional pixels weighted by their coverage.
RgbPlane boxDownsample(const RgbPlane& src, int width, int height, int nthreads);

// boxDownsample of an image whose rows arrive in order, full resolution: each output row is
// computed as soon as the input rows it covers have arrived, with the same sums in the same
// order, and input rows no longer needed are dropped. Memory: the output and a few rows.
class BoxDownsampler {
public:
    BoxDownsampler(int srcWidth, int srcHeight, int width, int height);
    ~BoxDownsampler();
    // Input row `y` (the next one), RGB floats `pixelStride` floats apart.
    void addRow(int y, const float* rgb, size_t pixelStride);
    // The downsampled plane; complete once every input row has been added.
    const RgbPlane& result() const { return m_out; }

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    RgbPlane m_out;
};

// Separable Gaussian of standard deviation `sigma` pixels with normalized weights, radius
// ceil(3σ), edges clamped.
RgbPlane gaussianBlur(const RgbPlane& src, float sigma, int nthreads);

// Bilinear sample at continuous pixel coordinates (pixel centres at integer + 0.5), edges
// clamped.
void bilinearSample(const RgbPlane& src, float fx, float fy, float out[3]);

} // namespace dhdr::detail
