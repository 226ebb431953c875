#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <dhdr/deferred/gbuffer.h>
#include <dhdr/deferred/light_culling.h>
#include <dhdr/deferred/light_eval.h>
#include <dhdr/deferred/lighting.h>

namespace dhdr {

namespace {

// What the shading loop reads first for every candidate light, packed by field (structure of
// arrays): enough to skip a light whose range does not reach the pixel without touching the
// rest of it.
struct LightReach {
    std::vector<float> x, y, z, range2;

    explicit LightReach(const std::vector<Light>& lights) {
        for (const Light& l : lights) {
            const bool bounded = l.isLocal() && std::isfinite(l.range);
            x.push_back(l.position.x);
            y.push_back(l.position.y);
            z.push_back(l.position.z);
            range2.push_back(bounded ? l.range * l.range : INFINITY);
        }
    }
    // False when the light's window is zero at P.
    bool reaches(std::uint32_t i, const glm::vec3& P) const {
        const float dx = x[i] - P.x, dy = y[i] - P.y, dz = z[i] - P.z;
        return dx * dx + dy * dy + dz * dz < range2[i];
    }
};

} // namespace

bool shadeGBuffer(OIIO::ImageBuf& dst, const OIIO::ImageBuf& gbuf, const std::vector<Light>& lights,
                  const LightingParams& params, LightingStats* stats, int nthreads) {
    const OIIO::ImageSpec& in = gbuf.spec();
    gbuffer::Layout layout;
    std::string missing;
    if (!gbuffer::findLayout(in, layout, missing)) {
        dst.errorfmt("no channel '{}' — is this a G-buffer?", missing);
        return false;
    }
    gbuffer::CameraInfo camera;
    if (std::string error; !gbuffer::readCamera(in, camera, error)) {
        dst.errorfmt("{}", error);
        return false;
    }
    std::vector<int> passIndex;
    for (const std::string& name : params.passThrough) {
        const int c = in.channelindex(name);
        if (c < 0) {
            dst.errorfmt("no channel '{}' to pass through", name);
            return false;
        }
        passIndex.push_back(c);
    }
    if (params.tileSize <= 0) {
        dst.errorfmt("tile size must be positive");
        return false;
    }
    OIIO::ImageBuf floatCopy;
    const OIIO::ImageBuf* src = &gbuf;
    if (in.format != OIIO::TypeDesc::FLOAT || !gbuf.localpixels()) {
        floatCopy = gbuf.copy(OIIO::TypeDesc::FLOAT);
        src = &floatCopy;
    }

    OIIO::ImageSpec spec = in;
    spec.nchannels = 4 + int(passIndex.size());
    spec.channelnames = {"R", "G", "B", "A"};
    for (const std::string& name : params.passThrough)
        spec.channelnames.push_back(name);
    spec.alpha_channel = 3;
    spec.z_channel = spec.channelindex("Z");
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.channelformats.clear();
    const OIIO::ImageSpec& held = dst.spec();
    if (dst.initialized() && dst.localpixels() && held.format == OIIO::TypeDesc::FLOAT &&
        held.channelformats.empty() && held.nchannels == spec.nchannels &&
        held.width == spec.width && held.height == spec.height) {
        dst.specmod() = spec;
    } else {
        dst.reset(spec, OIIO::InitializePixels::No);
    }

    // The frame the tiles are laid over; the G-buffer may be a strip of its rows.
    const OIIO::ROI frame = params.frame.defined() ? params.frame : gbuf.roi();
    if (in.x != frame.xbegin || in.width != frame.width() || in.y < frame.ybegin ||
        in.y + in.height > frame.yend) {
        dst.errorfmt("the G-buffer is not a strip of whole rows of the frame");
        return false;
    }
    const int frameWidth = frame.width(), frameHeight = frame.height();
    const size_t nch = size_t(src->nchannels());
    const DepthView depth{static_cast<const float*>(src->localpixels()) + layout.depth, nch,
                          nch * size_t(in.width), in.y - frame.ybegin};
    TileLightLists tiles;
    if (!params.bruteForce)
        tiles.build(lights, camera, depth, frameWidth, frameHeight, params.tileSize, nthreads,
                    in.y - frame.ybegin, in.y + in.height - frame.ybegin);
    const LightReach reach(lights);
    std::atomic<long long> evaluations{0}, reaching{0}, covered{0};
    OIIO::ImageBufAlgo::parallel_image(dst.roi(), OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        long long localEvaluations = 0, localReaching = 0, localCovered = 0;
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                const float* g = static_cast<const float*>(src->pixeladdr(x, y));
                float* out = static_cast<float*>(dst.pixeladdr(x, y));
                for (size_t k = 0; k < passIndex.size(); ++k)
                    out[4 + k] = g[passIndex[k]];
                const float coverage = g[layout.coverage];
                if (!(coverage > 0.0f)) {
                    std::copy(params.background, params.background + 4, out);
                    continue;
                }
                const glm::vec3 P(g[layout.position], g[layout.position + 1],
                                  g[layout.position + 2]);
                const glm::vec3 N = glm::normalize(
                    glm::vec3(g[layout.normal], g[layout.normal + 1], g[layout.normal + 2]));
                const glm::vec3 V(camera.toEye(P));
                PbrSurface s;
                s.baseColor =
                    glm::vec3(g[layout.albedo], g[layout.albedo + 1], g[layout.albedo + 2]);
                s.roughness = std::clamp(g[layout.roughness], 0.0f, 1.0f);
                s.metallic = std::clamp(g[layout.metallic], 0.0f, 1.0f);
                glm::vec3 Lo(0.0f);
                if (layout.emission >= 0)
                    Lo = glm::vec3(g[layout.emission], g[layout.emission + 1],
                                   g[layout.emission + 2]);
                if (params.bruteForce) {
                    // The reference: every light's full evaluation, which is exactly zero
                    // where it does not reach.
                    for (std::uint32_t i = 0; i < lights.size(); ++i) {
                        localReaching += reach.reaches(i, P);
                        Lo += shadeLight(lights[i], s, P, N, V);
                    }
                    localEvaluations += (long long)lights.size();
                } else {
                    const int px = x - frame.xbegin, py = y - frame.ybegin;
                    const std::uint32_t slice = tiles.sliceBit(px, py, g[layout.depth]);
                    for (const TileLightLists::Entry& e : tiles.at(px, py)) {
                        if (!(e.depthMask & slice)) continue;
                        ++localEvaluations;
                        // Out of range, the window is exactly zero: skip before reading more.
                        if (!reach.reaches(e.light, P)) continue;
                        ++localReaching;
                        Lo += shadeLight(lights[e.light], s, P, N, V);
                    }
                }
                ++localCovered;
                out[0] = Lo.r;
                out[1] = Lo.g;
                out[2] = Lo.b;
                out[3] = coverage;
            }
        evaluations += localEvaluations;
        reaching += localReaching;
        covered += localCovered;
    });
    if (stats) {
        stats->lightEvaluations = evaluations;
        stats->lightsReaching = reaching;
        stats->coveredPixels = covered;
        stats->tileListEntries = (long long)tiles.totalEntries();
    }
    return true;
}

} // namespace dhdr
