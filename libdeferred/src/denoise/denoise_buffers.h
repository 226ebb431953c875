// The planes the à-trous filter (denoise.h) reads and writes, laid out for its lanes: the guide
// and, per estimate, two buffers (one pass reads one and writes the other), set up from the
// inputs on every thread.
#pragma once

#include <algorithm>
#include <dhdr/deferred/denoise/denoise_inputs.h>
#include <memory>
#include <vector>

namespace dhdr {

// The B-spline of the filter's taps (1/4, 1/2, 1/4): 3 × 3 taps a pass.
inline constexpr int kDenoiseRadius = 1;
// The filter runs on 4 or 8 pixels of a row at once (denoise_lanes.h); rows are padded with
// pixels without a surface by the widest step's reach on either side, and to a whole number of
// the widest lanes, so that no tap needs a bounds check.
inline constexpr int kDenoiseMaxLanes = 8;
inline constexpr int kDenoisePad = std::max(2, kDenoiseRadius << (kDenoiseIterations - 1));

// One plane of floats per quantity, rows padded (kDenoisePad each side, the width rounded up
// to the lanes). Allocated without initialising: FilterBuffers writes every row, on every
// thread, so that a strip's planes are not first zeroed on one.
struct Planes {
    int stride = 0;
    std::unique_ptr<float[]> values;
    float* row(int y) { return values.get() + size_t(y) * size_t(stride) + kDenoisePad; }
    const float* row(int y) const {
        return values.get() + size_t(y) * size_t(stride) + kDenoisePad;
    }
    void allocate(int rowStride, int height) {
        stride = rowStride;
        values.reset(new float[size_t(stride) * size_t(height)]);
    }
    // Row y: value(x) for x in [0, width), zero in the padding.
    template <class Value>
    void fill(int y, int width, Value&& value) {
        float* r = row(y);
        std::fill(r - kDenoisePad, r, 0.0f);
        for (int x = 0; x < width; ++x)
            r[x] = value(x);
        std::fill(r + width, r - kDenoisePad + stride, 0.0f);
    }
    void zero(int y) { std::fill_n(row(y) - kDenoisePad, stride, 0.0f); }
};

// The guide: positions, normals, object and surface (1 or 0) as planes.
struct Guide {
    int width = 0, height = 0, stride = 0;
    Planes px, py, pz, nx, ny, nz, object, surface;
};

class Unsettled;

// Per estimate, one buffer: its signal (the ratio of a pair of planes, shadowed over unshadowed
// light, 1 where nothing was seen; or the one plane's value), its variance and its planes.
struct EstimateState {
    Planes signal, variance, plane[2];
    const Planes* direction[3] = {nullptr, nullptr, nullptr};
    const Planes* width = nullptr;
    const Planes* active = nullptr; // 1 where the estimate exists; null: wherever a surface is
    const Unsettled* unsettled = nullptr; // null: filtered wherever it exists
};

// The guide, and both buffers of every estimate holding its input (a variance of 0), with the
// planes of its mask and lobe (estimates guided by the same lobe share them).
struct FilterBuffers {
    Guide guide;
    std::vector<Planes> lobes;
    std::vector<EstimateState> state, next;

    FilterBuffers(const std::vector<DenoiseEstimate>& estimates, const DenoiseGuide& dg,
                  int nthreads);
};

} // namespace dhdr
