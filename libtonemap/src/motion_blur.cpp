#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <dhdr/tonemap/motion_blur.h>
#include <memory>
#include <vector>

namespace dhdr {

namespace {

int floorDiv(int a, int b) {
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// The per-pixel jitter of the taps, in [−0.5, 0.5): a hash of the pixel (the paper's noise
// texture), so that neighbours' taps interleave and the result is the same on any thread.
float jitter(int x, int y) {
    std::uint64_t h = (std::uint64_t(std::uint32_t(x)) << 32) ^ std::uint32_t(y);
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return float(h >> 40) * (1.0f / 16777216.0f) - 0.5f;
}

// cone(d, v) = clamp(1 − d / |v|): a point blurred over |v| reaches d at that weight.
float cone(float d, float v) {
    return std::clamp(1.0f - d / v, 0.0f, 1.0f);
}

// 1 − smoothstep(0.95 |v|, 1.05 |v|, d): a point blurred over |v| covers d fully.
float cylinder(float d, float v) {
    const float t = std::clamp((d - 0.95f * v) / (0.1f * v), 0.0f, 1.0f);
    return 1.0f - t * t * (3.0f - 2.0f * t);
}

// How much a surface at depth `a` is in front of one at `b` (1 at the same depth or nearer,
// 0 beyond the soft extent): the paper's softDepthCompare for distances (larger is farther).
// The background, +∞, is behind every surface and level with itself.
float inFront(float a, float b, float softness) {
    const bool fa = std::isfinite(a), fb = std::isfinite(b);
    if (!fa || !fb) return fa || !fb ? 1.0f : 0.0f;
    const float extent = std::max(softness * std::min(a, b), 1e-6f);
    return std::clamp(1.0f - (a - b) / extent, 0.0f, 1.0f);
}

// The blur vectors of the pixels the buffers hold, at most maxBlur long, and their tiles' and
// neighbourhoods' longest: tile (tx, ty) covers pixels [tx K, tx K + K) × [ty K, ty K + K) of
// the frame's coordinates, so that a strip and the whole frame agree.
struct Velocities {
    OIIO::ROI area; // the pixels held
    int K = 1;
    int tx0 = 0, ty0 = 0, tw = 0, th = 0; // the tiles computed
    std::vector<glm::vec2> pixel, neighbourMax;

    const glm::vec2& at(int x, int y) const {
        return pixel[size_t(y - area.ybegin) * size_t(area.width()) + size_t(x - area.xbegin)];
    }
    const glm::vec2& neighbourhood(int x, int y) const {
        return neighbourMax[size_t(floorDiv(y, K) - ty0) * size_t(tw) +
                            size_t(floorDiv(x, K) - tx0)];
    }
};

glm::vec2 longer(const glm::vec2& a, const glm::vec2& b) {
    return glm::dot(b, b) > glm::dot(a, a) ? b : a;
}

Velocities velocities(const detail::FloatPixels& motion, OIIO::ROI area, OIIO::ROI roi,
                      const MotionBlurParams& params, int nthreads) {
    Velocities v;
    v.area = area;
    v.K = params.maxBlur;
    const int K = v.K, w = area.width();
    v.pixel.resize(size_t(w) * size_t(area.height()));
    OIIO::ImageBufAlgo::parallel_image(area, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                const float* m = motion.at(x, y);
                glm::vec2 u = std::isfinite(m[0] + m[1] + m[2] + m[3])
                                  ? motionBlurVector(m, params.shutter)
                                  : glm::vec2(0.0f);
                const float length = glm::length(u);
                if (length > float(K)) u *= float(K) / length;
                v.pixel[size_t(y - area.ybegin) * size_t(w) + size_t(x - area.xbegin)] = u;
            }
    });
    // The tiles of roi and one around them: each within the pixels held.
    v.tx0 = floorDiv(roi.xbegin, K) - 1;
    v.ty0 = floorDiv(roi.ybegin, K) - 1;
    v.tw = floorDiv(roi.xend - 1, K) + 2 - v.tx0;
    v.th = floorDiv(roi.yend - 1, K) + 2 - v.ty0;
    std::vector<glm::vec2> tileMax(size_t(v.tw) * size_t(v.th), glm::vec2(0.0f));
    for (int ty = 0; ty < v.th; ++ty)
        for (int tx = 0; tx < v.tw; ++tx) {
            glm::vec2 longest(0.0f);
            const int x0 = std::max((v.tx0 + tx) * K, area.xbegin);
            const int x1 = std::min((v.tx0 + tx + 1) * K, area.xend);
            const int y0 = std::max((v.ty0 + ty) * K, area.ybegin);
            const int y1 = std::min((v.ty0 + ty + 1) * K, area.yend);
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x)
                    longest = longer(longest, v.at(x, y));
            tileMax[size_t(ty) * size_t(v.tw) + size_t(tx)] = longest;
        }
    v.neighbourMax.assign(tileMax.size(), glm::vec2(0.0f));
    for (int ty = 0; ty < v.th; ++ty)
        for (int tx = 0; tx < v.tw; ++tx) {
            glm::vec2 longest(0.0f);
            for (int j = std::max(ty - 1, 0); j <= std::min(ty + 1, v.th - 1); ++j)
                for (int i = std::max(tx - 1, 0); i <= std::min(tx + 1, v.tw - 1); ++i)
                    longest = longer(longest, tileMax[size_t(j) * size_t(v.tw) + size_t(i)]);
            v.neighbourMax[size_t(ty) * size_t(v.tw) + size_t(tx)] = longest;
        }
    return v;
}

} // namespace

bool validate(const MotionBlurParams& p, std::string& error) {
    if (!(p.shutter >= 0.0f && p.shutter <= 2.0f))
        error = "the shutter must be within [0, 2] frames";
    else if (p.samples < 1 || p.samples > 256)
        error = "the samples must be within [1, 256]";
    else if (p.maxBlur < 1 || p.maxBlur > 128)
        error = "the longest blur must be within [1, 128] pixels";
    else if (!(p.depthSoftness > 0.0f && p.depthSoftness <= 1.0f))
        error = "the depth softness must be within (0, 1]";
    else
        return true;
    return false;
}

bool motionBlur(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const OIIO::ImageBuf& motion,
                const OIIO::ImageBuf& depth, const MotionBlurParams& params, OIIO::ROI roi,
                int nthreads) {
    std::string error;
    if (!validate(params, error)) {
        dst.errorfmt("{}", error);
        return false;
    }
    if (src.deep() || motion.deep() || depth.deep()) {
        dst.errorfmt("motion blur takes flat images, not deep ones");
        return false;
    }
    if (motion.nchannels() < 4 || depth.nchannels() < 1) {
        dst.errorfmt("motion blur needs 4 motion channels and a depth channel");
        return false;
    }
    // The pixels every input holds.
    OIIO::ROI area =
        OIIO::roi_intersection(src.roi(), OIIO::roi_intersection(motion.roi(), depth.roi()));
    if (!roi.defined()) roi = src.roi();
    roi.chend = std::min(roi.chend, src.nchannels());
    if (!area.defined() || roi.xbegin < area.xbegin || roi.xend > area.xend ||
        roi.ybegin < area.ybegin || roi.yend > area.yend) {
        dst.errorfmt("the image, motion and depth do not all cover the region filtered");
        return false;
    }
    area.chbegin = 0;
    area.chend = 1;
    // Filtering reads neighbours, so an in-place call works from a copy.
    std::unique_ptr<OIIO::ImageBuf> copy;
    const OIIO::ImageBuf* source = &src;
    if (&dst == &src) {
        copy = std::make_unique<OIIO::ImageBuf>(src.copy(OIIO::TypeDesc::FLOAT));
        source = copy.get();
    }
    if (!detail::prepareFloatDst(dst, *source, roi, 1)) return false;
    const detail::FloatPixels in(*source), M(motion), Z(depth);
    const Velocities v = velocities(M, area, roi, params, nthreads);
    const int nch = roi.chend, S = params.samples;
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        std::vector<double> sum(static_cast<size_t>(nch));
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                const float* p = in.at(x, y);
                float* q = detail::floatPixel(dst, x, y);
                const glm::vec2 vn = v.neighbourhood(x, y);
                if (!(glm::dot(vn, vn) >= 0.25f)) {
                    std::copy(p, p + nch, q);
                    continue;
                }
                // McGuire et al. 2012, Listing 1 (reconstruct): the pixel itself by 1 / |V|,
                // then taps along the neighbourhood's longest blur, each weighted by whether
                // it is in front and blurred over this pixel, or behind and this pixel blurred
                // over it, or both blurred over each other.
                const float zx = *Z.at(x, y);
                const float vx = std::max(glm::length(v.at(x, y)), 0.5f);
                double weight = 1.0 / vx;
                for (int c = 0; c < nch; ++c)
                    sum[size_t(c)] = double(p[c]) * weight;
                const float j = jitter(x, y);
                for (int i = 0; i < S; ++i) {
                    if (S > 2 && S % 2 == 1 && i == (S - 1) / 2) continue; // the pixel itself
                    const float t = -1.0f + 2.0f * (float(i) + j + 1.0f) / float(S + 1);
                    // Nearest pixel (floor(v + ½), as lround but without the call).
                    const int sx = std::clamp(int(std::floor(float(x) + vn.x * t + 0.5f)),
                                              area.xbegin, area.xend - 1);
                    const int sy = std::clamp(int(std::floor(float(y) + vn.y * t + 0.5f)),
                                              area.ybegin, area.yend - 1);
                    const float dx = float(sx - x), dy = float(sy - y);
                    const float d = std::sqrt(dx * dx + dy * dy);
                    const float zy = *Z.at(sx, sy);
                    const float vy = std::max(glm::length(v.at(sx, sy)), 0.5f);
                    const float front = inFront(zy, zx, params.depthSoftness);
                    const float back = inFront(zx, zy, params.depthSoftness);
                    const float a = front * cone(d, vy) + back * cone(d, vx) +
                                    2.0f * cylinder(d, vy) * cylinder(d, vx);
                    if (!(a > 0.0f)) continue;
                    const float* s = in.at(sx, sy);
                    for (int c = 0; c < nch; ++c)
                        sum[size_t(c)] += double(s[c]) * a;
                    weight += a;
                }
                for (int c = 0; c < nch; ++c)
                    q[c] = float(sum[size_t(c)] / weight);
            }
    });
    return true;
}

} // namespace dhdr
