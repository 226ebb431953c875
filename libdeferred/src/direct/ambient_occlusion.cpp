#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/direct/ambient_occlusion.h>
#include <dhdr/deferred/gbuffer/shading_point.h>
#include <vector>

namespace dhdr {

float rayTracedOcclusion(const SurfacePoint& at, const glm::vec3& N, std::uint64_t seed,
                         int samples, float distance, const Visibility& visibility,
                         long long* rays) {
    if (samples <= 0) return 1.0f;
    glm::vec3 t, b;
    orthonormalBasis(N, t, b);
    constexpr int kBatch = 64;
    // Per thread, so that the rays are not value-initialized again at every pixel.
    thread_local ShadowRay batch[kBatch];
    float transmittance[kBatch];
    const RotatedHammersley sequence(seed);
    // Summed in sample order in double: the same for any thread count.
    double open = 0.0;
    int traced = 0;
    for (int begin = 0; begin < samples; begin += kBatch) {
        int n = 0;
        for (int i = begin; i < std::min(samples, begin + kBatch); ++i) {
            const glm::vec3 d =
                cosineHemisphere(sequence(std::uint32_t(i), std::uint32_t(samples)));
            const glm::vec3 w = glm::normalize(t * d.x + b * d.y + N * d.z);
            // Below the triangle's own plane (a smooth normal at a silhouette or a terminator):
            // the ray would meet the surface it leaves; such directions are not the sky's.
            if (!(glm::dot(at.Ng, w) > 0.0f)) continue;
            batch[n++] = {offsetRayOrigin(at, w), w, distance};
        }
        visibility.test(batch, size_t(n), transmittance);
        for (int i = 0; i < n; ++i)
            open += double(transmittance[i]);
        traced += n;
    }
    if (rays) *rays += traced;
    return traced > 0 ? float(open / traced) : 1.0f;
}

namespace {

float smoothstep01(float x) {
    x = std::clamp(x, 0.0f, 1.0f);
    return x * x * (3.0f - 2.0f * x);
}

bool checkSsaoParams(const SsaoParams& params, OIIO::ImageBuf& dst) {
    if (const std::string error = checkRanges(params, kSsaoParamTable); !error.empty()) {
        dst.errorfmt("SSAO {}", error);
        return false;
    }
    if (!(params.radius > 0.0f)) {
        dst.errorfmt("SSAO radius must be positive");
        return false;
    }
    return true;
}

// The kernel: points in the unit hemisphere about +Z, denser near the centre (scaled by
// lerp(0.1, 1, (i/K)²), as in the seed), from a Hammersley set.
std::vector<glm::vec3> ssaoKernel(int samples) {
    std::vector<glm::vec3> kernel;
    for (int i = 0; i < samples; ++i) {
        const glm::vec2 u = hammersley(std::uint32_t(i), std::uint32_t(samples), 0);
        const float s = float(i) / float(samples);
        kernel.push_back(cosineHemisphere(u) * (0.1f + 0.9f * s * s));
    }
    return kernel;
}

// The G-buffer's pixels as the screen-space pass reads them: surfaces, and points projected
// back onto the screen.
class SsaoFrame {
public:
    SsaoFrame(const GBufferPixels& g, const OIIO::ImageSpec& in)
        : W(in.width), H(in.height), m_layout(g.layout), m_nch(size_t(in.nchannels)),
          m_pixels(static_cast<const float*>(g.pixels->localpixels())),
          m_toCamera(g.camera.worldToCamera), m_toNDC(g.camera.worldToNDC) {}

    const int W, H;

    bool covered(int x, int y) const { return at(x, y)[m_layout.coverage] > 0.0f; }

    // 1 − the occlusion of covered pixel (x, y) by the surfaces the kernel's points fall
    // behind, the kernel turned by the pixel's place in its 4 × 4 block.
    float openness(int x, int y, const std::vector<glm::vec3>& kernel,
                   const SsaoParams& params) const {
        const float* g = at(x, y);
        const glm::vec3 P = position(g);
        const glm::vec3 N = glm::normalize(
            glm::vec3(g[m_layout.normal], g[m_layout.normal + 1], g[m_layout.normal + 2]));
        // The 4 × 4 block's rotation: 16 angles spread evenly, in a fixed shuffle.
        static constexpr int kOrder[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};
        const float angle = 2.0f * kPi * float(kOrder[(y & 3) * 4 + (x & 3)]) / 16.0f;
        glm::vec3 t, b;
        orthonormalBasis(N, t, b);
        const float c = std::cos(angle), s = std::sin(angle);
        const glm::vec3 tr = c * t + s * b, br = -s * t + c * b;
        const float depthP = depthOf(P);
        float occlusion = 0.0f;
        for (const glm::vec3& k : kernel) {
            const glm::vec3 S = P + (tr * k.x + br * k.y + N * k.z) * params.radius;
            const glm::dvec4 clip = m_toNDC * glm::dvec4(glm::dvec3(S), 1.0);
            if (!(clip.w > 0.0)) continue;
            const int sx = int(std::floor((clip.x / clip.w + 1.0) * 0.5 * W));
            const int sy = int(std::floor((1.0 - clip.y / clip.w) * 0.5 * H));
            if (sx < 0 || sy < 0 || sx >= W || sy >= H) continue;
            const float* q = at(sx, sy);
            if (!(q[m_layout.coverage] > 0.0f)) continue;
            const float surface = depthOf(position(q));
            if (surface <= depthOf(S) - params.bias)
                occlusion +=
                    smoothstep01(params.radius / std::max(std::abs(depthP - surface), 1e-20f));
        }
        return 1.0f - occlusion / float(params.samples);
    }

private:
    const float* at(int x, int y) const {
        return m_pixels + (size_t(y) * size_t(W) + size_t(x)) * m_nch;
    }
    glm::vec3 position(const float* g) const {
        return glm::vec3(g[m_layout.position], g[m_layout.position + 1], g[m_layout.position + 2]);
    }
    // Distance in front of the camera along its axis.
    float depthOf(const glm::vec3& p) const {
        return float(-(m_toCamera * glm::dvec4(glm::dvec3(p), 1.0)).z);
    }

    const gbuffer::Layout& m_layout;
    const size_t m_nch;
    const float* m_pixels;
    const glm::dmat4 m_toCamera, m_toNDC;
};

// The AO image's spec: one channel over the G-buffer's windows.
OIIO::ImageSpec aoSpec(const OIIO::ImageSpec& in) {
    OIIO::ImageSpec spec(in.width, in.height, 1, OIIO::TypeDesc::FLOAT);
    spec.x = in.x;
    spec.y = in.y;
    spec.full_x = in.full_x;
    spec.full_y = in.full_y;
    spec.full_width = in.full_width;
    spec.full_height = in.full_height;
    spec.channelnames = {"AO"};
    return spec;
}

// The 4 × 4 box blur of the seed (offsets −2…1), over covered pixels only, undoes the block's
// rotation pattern; uncovered pixels are open.
void blurAO(const std::vector<float>& raw, const std::vector<unsigned char>& covered, int W, int H,
            float* out, int nthreads) {
    parallelImageRows(OIIO::ROI(0, W, 0, H), nthreads, [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                const size_t i = size_t(y) * size_t(W) + size_t(x);
                if (!covered[i]) {
                    out[i] = 1.0f;
                    continue;
                }
                float sum = 0.0f;
                int n = 0;
                for (int dy = -2; dy < 2; ++dy)
                    for (int dx = -2; dx < 2; ++dx) {
                        const int u = x + dx, v = y + dy;
                        if (u < 0 || v < 0 || u >= W || v >= H) continue;
                        const size_t j = size_t(v) * size_t(W) + size_t(u);
                        if (!covered[j]) continue;
                        sum += raw[j];
                        ++n;
                    }
                out[i] = std::clamp(sum / float(n), 0.0f, 1.0f);
            }
    });
}

} // namespace

bool screenSpaceAO(OIIO::ImageBuf& dst, const OIIO::ImageBuf& gbuf, const SsaoParams& params,
                   int nthreads) {
    if (!checkSsaoParams(params, dst)) return false;
    GBufferPixels g;
    if (!openGBuffer(gbuf, g, dst)) return false;
    const SsaoFrame frame(g, gbuf.spec());
    const int W = frame.W, H = frame.H;
    const std::vector<glm::vec3> kernel = ssaoKernel(params.samples);
    std::vector<float> raw(size_t(W) * size_t(H), 1.0f);
    std::vector<unsigned char> covered(raw.size(), 0);
    parallelImageRows(OIIO::ROI(0, W, 0, H), nthreads, [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                if (!frame.covered(x, y)) continue;
                covered[size_t(y) * size_t(W) + size_t(x)] = 1;
                raw[size_t(y) * size_t(W) + size_t(x)] = frame.openness(x, y, kernel, params);
            }
    });
    dst.reset(aoSpec(gbuf.spec()));
    blurAO(raw, covered, W, H, static_cast<float*>(dst.localpixels()), nthreads);
    return true;
}

} // namespace dhdr
