#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <dhdr/tonemap/edge_aa.h>
#include <memory>
#include <optional>
#include <vector>

namespace dhdr {

namespace {

constexpr int kNeighbours[8][2] = {{-1, -1}, {0, -1}, {1, -1}, {-1, 0},
                                   {1, 0},   {-1, 1}, {0, 1},  {1, 1}};

// (Z_k − Z) / Z for one neighbour; background depth (+∞) against a surface counts as a full
// edge, background against background as none.
double relativeDepthStep(float z, float zk) {
    const bool finite = std::isfinite(z), finiteK = std::isfinite(zk);
    if (!finite || !finiteK) return finite == finiteK ? 0.0 : 1.0;
    const double near = std::max(std::min(double(z), double(zk)), 1e-6);
    return (double(zk) - double(z)) / near;
}

} // namespace

bool edgeBlurFactor(OIIO::ImageBuf& dst, const OIIO::ImageBuf* normal, const OIIO::ImageBuf* depth,
                    const EdgeAAParams& params, OIIO::ROI roi, int nthreads) {
    if (!normal && !depth) {
        dst.errorfmt("edge AA needs a normal or a depth image");
        return false;
    }
    if ((normal && normal->deep()) || (depth && depth->deep())) {
        dst.errorfmt("edge AA takes flat geometry images, not deep ones");
        return false;
    }
    if (normal && normal->nchannels() < 3) {
        dst.errorfmt("the normal image needs 3 channels");
        return false;
    }
    const OIIO::ImageBuf& geometry = normal ? *normal : *depth;
    if (!roi.defined()) roi = geometry.roi();
    auto samePixels = [](const OIIO::ROI& a, const OIIO::ROI& b) {
        return a.xbegin == b.xbegin && a.xend == b.xend && a.ybegin == b.ybegin && a.yend == b.yend;
    };
    if (normal && depth && !samePixels(normal->roi(), depth->roi())) {
        dst.errorfmt("normal and depth images differ in size");
        return false;
    }
    std::optional<detail::FloatPixels> N, Z;
    if (normal) N.emplace(*normal);
    if (depth) Z.emplace(*depth);

    OIIO::ImageSpec spec = geometry.spec();
    spec.nchannels = 1;
    spec.channelnames = {"edge"};
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.channelformats.clear();
    dst.reset(spec);
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                double e = 0.0;
                for (const auto& o : kNeighbours) {
                    if (N) {
                        const float* n = N->at(x, y);
                        const float* nk = N->clamped(x + o[0], y + o[1]);
                        double d2 = 0.0;
                        for (int c = 0; c < 3; ++c)
                            d2 += double(nk[c] - n[c]) * (nk[c] - n[c]);
                        e += params.normalWeight * d2;
                    }
                    if (Z) {
                        const double s =
                            relativeDepthStep(*Z->at(x, y), *Z->clamped(x + o[0], y + o[1]));
                        e += params.depthWeight * s * s;
                    }
                }
                *detail::floatPixel(dst, x, y) = float(std::min(1.0, e));
            }
    });
    return true;
}

bool edgeAA(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const OIIO::ImageBuf* normal,
            const OIIO::ImageBuf* depth, const EdgeAAParams& params, OIIO::ROI roi, int nthreads) {
    if (src.deep() || (normal && normal->deep()) || (depth && depth->deep())) {
        dst.errorfmt("edge AA takes flat images, not deep ones");
        return false;
    }
    const OIIO::ImageBuf& geometry = normal ? *normal : *depth;
    if ((normal || depth) && geometry.roi().width() != src.roi().width()) {
        dst.errorfmt("geometry images are {}x{}, the image is {}x{}", geometry.spec().width,
                     geometry.spec().height, src.spec().width, src.spec().height);
        return false;
    }
    if ((normal || depth) && geometry.roi().height() != src.roi().height()) {
        dst.errorfmt("geometry images are {}x{}, the image is {}x{}", geometry.spec().width,
                     geometry.spec().height, src.spec().width, src.spec().height);
        return false;
    }
    OIIO::ImageBuf factor;
    if (!edgeBlurFactor(factor, normal, depth, params, {}, nthreads)) {
        dst.errorfmt("{}", factor.geterror());
        return false;
    }
    // Filtering reads neighbours, so an in-place call works from a copy.
    std::unique_ptr<OIIO::ImageBuf> copy;
    const OIIO::ImageBuf* source = &src;
    if (&dst == &src) {
        copy = std::make_unique<OIIO::ImageBuf>(src.copy(OIIO::TypeDesc::FLOAT));
        source = copy.get();
    }
    if (!detail::prepareFloatDst(dst, *source, roi, 1)) return false;
    const detail::FloatPixels in(*source);
    const detail::FloatPixels edge(factor);
    const int nch = roi.chend;
    const OIIO::ROI full = source->roi();
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        std::vector<double> sum(static_cast<size_t>(nch));
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                const float e = *edge.at(x - full.xbegin + geometry.roi().xbegin,
                                         y - full.ybegin + geometry.roi().ybegin);
                float* q = detail::floatPixel(dst, x, y);
                const float* p = in.at(x, y);
                if (e == 0.0f) {
                    std::copy(p, p + nch, q);
                    continue;
                }
                std::fill(sum.begin(), sum.end(), 0.0);
                const float step = e * params.maxOffset;
                for (const auto& o : kNeighbours) {
                    // Bilinear tap at (x, y) + step · o.
                    const float fx = float(x) + step * float(o[0]);
                    const float fy = float(y) + step * float(o[1]);
                    const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
                    const float tx = fx - float(x0), ty = fy - float(y0);
                    const float* a = in.clamped(x0, y0);
                    const float* b = in.clamped(x0 + 1, y0);
                    const float* c = in.clamped(x0, y0 + 1);
                    const float* d = in.clamped(x0 + 1, y0 + 1);
                    for (int k = 0; k < nch; ++k)
                        sum[size_t(k)] += (1 - ty) * ((1 - tx) * a[k] + tx * b[k]) +
                                          ty * ((1 - tx) * c[k] + tx * d[k]);
                }
                for (int k = 0; k < nch; ++k)
                    q[k] = float(sum[size_t(k)] / 8.0);
            }
    });
    return true;
}

} // namespace dhdr
