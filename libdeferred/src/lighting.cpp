#include <dhdr/deferred/lighting.h>

#include <dhdr/deferred/gbuffer.h>
#include <dhdr/deferred/light_bounds.h>
#include <dhdr/deferred/light_eval.h>

#include <OpenImageIO/imagebufalgo_util.h>

#include <algorithm>
#include <atomic>

namespace dhdr {

namespace {

// Per-tile light lists, each in ascending light index.
struct TileLists {
    int tileSize = 16, tilesX = 0, tilesY = 0;
    std::vector<std::vector<int>> lights;

    const std::vector<int>& at(int x, int y) const {
        return lights[size_t(y / tileSize) * size_t(tilesX) + size_t(x / tileSize)];
    }
};

TileLists buildTileLists(const std::vector<Light>& lights, const gbuffer::CameraInfo& camera,
                         int width, int height, int tileSize, bool bruteForce) {
    TileLists tiles;
    tiles.tileSize = tileSize;
    tiles.tilesX = (width + tileSize - 1) / tileSize;
    tiles.tilesY = (height + tileSize - 1) / tileSize;
    tiles.lights.resize(size_t(tiles.tilesX) * size_t(tiles.tilesY));
    const glm::dmat4 cameraToNDC = camera.worldToNDC * glm::inverse(camera.worldToCamera);
    for (int i = 0; i < int(lights.size()); ++i) {
        const PixelRect r =
            bruteForce ? PixelRect{0, 0, width, height}
                       : lightScreenRect(lights[size_t(i)], camera.worldToCamera, cameraToNDC,
                                         width, height);
        if (r.empty()) continue;
        for (int ty = r.y0 / tileSize; ty <= (r.y1 - 1) / tileSize; ++ty)
            for (int tx = r.x0 / tileSize; tx <= (r.x1 - 1) / tileSize; ++tx)
                tiles.lights[size_t(ty) * size_t(tiles.tilesX) + size_t(tx)].push_back(i);
    }
    return tiles;
}

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
    if (!gbuffer::readCamera(in, camera)) {
        dst.errorfmt("no worldToCamera/worldToNDC attributes — is this a G-buffer?");
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
    for (const std::string& name : params.passThrough) spec.channelnames.push_back(name);
    spec.alpha_channel = 3;
    spec.z_channel = spec.channelindex("Z");
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.channelformats.clear();
    dst.reset(spec);

    const TileLists tiles = buildTileLists(lights, camera, in.width, in.height, params.tileSize,
                                           params.bruteForce);
    const glm::vec3 eye(camera.position);
    std::atomic<long long> evaluations{0}, covered{0};
    OIIO::ImageBufAlgo::parallel_image(dst.roi(), OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        long long localEvaluations = 0, localCovered = 0;
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x) {
                const float* g = static_cast<const float*>(src->pixeladdr(x, y));
                float* out = static_cast<float*>(dst.pixeladdr(x, y));
                for (size_t k = 0; k < passIndex.size(); ++k) out[4 + k] = g[passIndex[k]];
                const float coverage = g[layout.coverage];
                if (!(coverage > 0.0f)) {
                    std::copy(params.background, params.background + 4, out);
                    continue;
                }
                const glm::vec3 P(g[layout.position], g[layout.position + 1],
                                  g[layout.position + 2]);
                const glm::vec3 N = glm::normalize(
                    glm::vec3(g[layout.normal], g[layout.normal + 1], g[layout.normal + 2]));
                const glm::vec3 V = glm::normalize(eye - P);
                PbrSurface s;
                s.baseColor = glm::vec3(g[layout.albedo], g[layout.albedo + 1],
                                        g[layout.albedo + 2]);
                s.roughness = std::clamp(g[layout.roughness], 0.0f, 1.0f);
                s.metallic = std::clamp(g[layout.metallic], 0.0f, 1.0f);
                glm::vec3 Lo(0.0f);
                if (layout.emission >= 0)
                    Lo = glm::vec3(g[layout.emission], g[layout.emission + 1],
                                   g[layout.emission + 2]);
                const std::vector<int>& list = tiles.at(x - in.x, y - in.y);
                for (int i : list) Lo += shadeLight(lights[size_t(i)], s, P, N, V);
                localEvaluations += (long long)list.size();
                ++localCovered;
                out[0] = Lo.r;
                out[1] = Lo.g;
                out[2] = Lo.b;
                out[3] = coverage;
            }
        evaluations += localEvaluations;
        covered += localCovered;
    });
    if (stats) {
        stats->lightEvaluations = evaluations;
        stats->coveredPixels = covered;
    }
    return true;
}

} // namespace dhdr
