// The lighting pass's Monte Carlo estimates, denoised: each environment light's shadow-ray
// sums, the ray-traced AO and a shadow catcher's bounce light of every pixel a flat G-buffer
// holds, estimated first and
// filtered over neighbouring pixels of the same surface (denoise.h), then read by the shading.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <cstdint>
#include <dhdr/deferred/direct/shadows.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/shading_point.h>
#include <dhdr/deferred/integrator/estimate_carry.h>
#include <dhdr/deferred/integrator/lighting_params.h>
#include <dhdr/deferred/scene/lights.h>
#include <vector>

namespace dhdr {

class BounceLighting;
class SpecularIndirect;

// The estimates that trace the scene: a shadow catcher's bounce light on the pixels of object
// `catcher` (id.object), params.catcherBounceSamples rays through `bounce`; the specular
// indirect light where it applies, params.specularSamples rays through `specular`.
struct TracedEstimates {
    const BounceLighting* bounce = nullptr;
    float catcher = 0.0f;
    const SpecularIndirect* specular = nullptr;
    bool probes = false; // rough lobes take the probes' light (SpecularIndirect::traced)
};

class FilteredEstimates {
public:
    // Estimates every covered pixel of `held` (a strip's halo rows included) with the seeds
    // the shading would use (the rows `carry` holds from the previous strip are taken from it;
    // this strip's last 2 kDenoiseReach rows are left in it for the next): shadow rays of each
    // environment light (found among `infinite`, the indices of the infinite lights of
    // `lights`, infiniteLights) through `shadowRays` (null: none), params.aoSamples AO rays through
    // `aoRays` (null: no AO). Nothing when params.denoise is off, the view is deep, or there is
    // nothing to estimate. With `traced`, the catcher's bounce light and the specular indirect
    // light too. Only the rows of `read` (within `held`; undefined: all) are read afterwards,
    // and only their results are filtered to the end.
    FilteredEstimates(const GBufferView& view, const gbuffer::Layout& layout, OIIO::ROI held,
                      OIIO::ROI read, const std::vector<Light>& lights,
                      const std::vector<std::uint32_t>& infinite, const LightingParams& params,
                      const Visibility* shadowRays, const Visibility* aoRays,
                      const TracedEstimates& traced, int nthreads, EstimateCarry* carry = nullptr);

    // Whether light i's visibility, or the AO, comes from here.
    bool filters(std::uint32_t light) const { return light < m_slot.size() && m_slot[light] >= 0; }
    bool filtersAO() const { return !m_ao.empty(); }
    // The filtered ratios of light i at pixel (x, y), diffuse and specular: 1 where no
    // neighbour saw its sky.
    EnvironmentVisibility visibility(std::uint32_t light, int x, int y) const;
    float ambientOcclusion(int x, int y) const;
    bool filtersBounce() const { return !m_bounce.empty(); }
    // The luminance of the light a catcher pixel reflects from the bounce: its diffuse albedo
    // (1 − metallic) × E / π, E the bounce irradiance (bounce_light.h).
    float catcherBounce(int x, int y) const { return m_bounce[index(x, y)]; }
    bool filtersSpecular() const { return !m_specular[0].empty(); }
    // The specular indirect light of a flat pixel (0 where it does not apply).
    glm::vec3 specularIndirect(int x, int y) const {
        const size_t p = index(x, y);
        return {m_specular[0][p], m_specular[1][p], m_specular[2][p]};
    }
    // The rays traced.
    long long shadowRayCount = 0, aoRayCount = 0, bounceRayCount = 0, specularRayCount = 0;

private:
    struct Pass; // what one call estimates and filters with

    void choose(Pass& pass, const std::vector<std::uint32_t>& infinite);
    void allocate(Pass& pass, OIIO::ROI read);
    void takeCarried(Pass& pass, const EstimateCarry::Rows* previous,
                     const std::vector<float*>& raw);
    struct Rays; // the rays one thread traced
    void estimateRows(Pass& pass, int nthreads);
    void estimatePixel(Pass& pass, int x, int y, bool carried, Rays& rays);
    void leaveCarry(EstimateCarry& carry, const std::vector<float*>& raw) const;
    void filter(Pass& pass, int nthreads);
    // Every plane of raw estimates, n = held.npixels() values each (a pair's two planes apart).
    std::vector<float*> planes();
    size_t index(int x, int y) const {
        return size_t(y - m_held.ybegin) * size_t(m_held.width()) + size_t(x - m_held.xbegin);
    }

    OIIO::ROI m_held;
    std::vector<int> m_slot; // per light, its pair of sums (−1: not filtered)
    // Per filtered light and part (diffuse, specular): Σ wV, then Σ w.
    std::vector<std::vector<float>> m_diffuse, m_specularRatio;
    std::vector<float> m_specular[3]; // the specular indirect light, R, G, B
    std::vector<float> m_ao, m_bounce;
};

} // namespace dhdr
