// The lighting pass's Monte Carlo estimates, denoised: each environment light's shadow-ray
// sums, the ray-traced AO, a shadow catcher's bounce light and the specular indirect light of
// every sample a G-buffer holds, estimated first and filtered over neighbouring pixels of the
// same surface and layer (denoise.h, sample_layers.h), then read by the shading.
#pragma once

#include "integrator/sample_layers.h"

#include <OpenImageIO/imagebuf.h>
#include <array>
#include <cstdint>
#include <dhdr/deferred/direct/shadows.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/shading_point.h>
#include <dhdr/deferred/integrator/estimate_carry.h>
#include <dhdr/deferred/integrator/lighting_params.h>
#include <dhdr/deferred/scene/lights.h>
#include <optional>
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
    // Estimates every sample of every covered pixel of `held` (a strip's halo rows included),
    // flat or deep, with the seeds the shading would use (the rows `carry` holds from the previous
    // strip are taken from it; this strip's last 2 kDenoiseReach rows are left in it for the next):
    // shadow rays of each environment light (found among `infinite`, the indices of the infinite
    // lights of `lights`, infiniteLights) through `shadowRays` (null: none), params.aoSamples AO
    // rays through `aoRays` (null: no AO). Nothing when params.denoise is off or there is nothing
    // to estimate. A deep view's samples are filtered layer by layer (sample_layers.h). With
    // `traced`, the catcher's bounce light and the specular indirect light too. Only the rows of
    // `read` (within `held`; undefined: all) are read afterwards, and only their results are
    // filtered to the end.
    FilteredEstimates(const GBufferView& view, const gbuffer::Layout& layout, OIIO::ROI held,
                      OIIO::ROI read, const std::vector<Light>& lights,
                      const std::vector<std::uint32_t>& infinite, const LightingParams& params,
                      const Visibility* shadowRays, const Visibility* aoRays,
                      const TracedEstimates& traced, int nthreads, EstimateCarry* carry = nullptr);

    // Whether light i's visibility, or the AO, comes from here.
    bool filters(std::uint32_t light) const { return light < m_slot.size() && m_slot[light] >= 0; }
    bool filtersAO() const { return !m_layers.empty() && !m_layers[0].ao.empty(); }
    bool filtersBounce() const { return !m_layers.empty() && !m_layers[0].bounce.empty(); }
    bool filtersSpecular() const { return !m_layers.empty() && !m_layers[0].specular[0].empty(); }
    // Of sample k of pixel (x, y) (0 for a flat pixel): the filtered ratios of light i,
    // diffuse and specular (1 where no neighbour saw its sky); the AO; the luminance of the
    // light a catcher reflects from the bounce (its diffuse albedo (1 − metallic) × E / π, E
    // the bounce irradiance, bounce_light.h); the specular indirect light (0 where it does not
    // apply).
    EnvironmentVisibility visibility(std::uint32_t light, int x, int y, int k) const;
    float ambientOcclusion(int x, int y, int k) const;
    float catcherBounce(int x, int y, int k) const {
        const Place at = placeOf(x, y, k);
        return m_layers[at.layer].bounce[at.pixel];
    }
    glm::vec3 specularIndirect(int x, int y, int k) const {
        const Place at = placeOf(x, y, k);
        const Planes& l = m_layers[at.layer];
        return {l.specular[0][at.pixel], l.specular[1][at.pixel], l.specular[2][at.pixel]};
    }
    // The rays traced.
    long long shadowRayCount = 0, aoRayCount = 0, bounceRayCount = 0, specularRayCount = 0;

private:
    struct Pass;  // what one call estimates and filters with
    struct Guide; // what guides the filter on one layer

    void choose(Pass& pass, const std::vector<std::uint32_t>& infinite);
    void allocate(Pass& pass, OIIO::ROI read);
    void takeCarried(Pass& pass, const EstimateCarry::Rows* previous,
                     const std::vector<float*>& raw);
    struct Rays; // the rays one thread traced
    void estimateRows(Pass& pass, int nthreads);
    void estimateSample(Pass& pass, int x, int y, int k, bool carried, Rays& rays);
    void leaveCarry(EstimateCarry& carry, const std::vector<float*>& raw) const;
    void filter(Pass& pass, int nthreads);
    // Every plane of raw estimates, n = held.npixels() values each (a pair's two planes apart),
    // layer after layer, each layer's in the same order.
    std::vector<float*> planes();
    size_t index(int x, int y) const {
        return size_t(y - m_held.ybegin) * size_t(m_held.width()) + size_t(x - m_held.xbegin);
    }

    // One layer's raw, then filtered, estimates, held.npixels() values a plane.
    struct Planes {
        // Per filtered light and part (diffuse, specular): Σ wV, then Σ w.
        std::vector<std::vector<float>> diffuse, specularRatio;
        std::vector<float> specular[3]; // the specular indirect light, R, G, B
        std::vector<float> ao, bounce;
    };
    // Where a sample's estimates are: its own layer and pixel, or its donor's (the samples of
    // a pixel's other rays, sample_layers.h).
    struct Place {
        size_t layer, pixel;
    };
    Place placeOf(int x, int y, int k) const;
    void findDonors(const GBufferView& view, const gbuffer::Layout& layout, int nthreads);

    OIIO::ROI m_held;
    std::vector<int> m_slot; // per light, its pair of sums (−1: not filtered)
    std::optional<SampleLayers> m_sampleLayers;
    // Only the layers some pixel of `held` reaches (one for a flat view). Each costs
    // (16 × filtered lights + 4 AO + 4 bounce + 12 specular) bytes a held pixel, and while it
    // is estimated and filtered ~45 bytes of guide a pixel more.
    std::vector<Planes> m_layers;
    // The donors of the samples without their own place, by GBufferView::sampleIndex from
    // m_donorBase (layer, pixel; kOwnPlace: the sample's own): 8 bytes a sample of a pixel of
    // several rays, where a hash map of them took ~50 and most of the pass's time.
    static constexpr std::uint32_t kOwnPlace = 0xffffffffu;
    std::vector<std::array<std::uint32_t, 2>> m_donors;
    size_t m_donorBase = 0;
    const GBufferView* m_view = nullptr;
};

} // namespace dhdr
