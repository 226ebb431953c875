// What the lighting pass (lighting.h) lights a G-buffer with, besides the parameters.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <dhdr/deferred/core/visibility.h>
#include <dhdr/deferred/integrator/estimate_carry.h>
#include <dhdr/deferred/scene/lights.h>
#include <functional>
#include <vector>

namespace dhdr {

struct ProbeVolume;
class RayCaster;

// What lights the G-buffer, besides its own emission.
struct LightingInputs {
    const std::vector<Light>& lights;
    // The scene, for shadow and ambient-occlusion rays (a RayCaster); null: nothing blocks
    // light and AO is 1 unless `ambientOcclusion` gives it.
    const Visibility* visibility = nullptr;
    // Precomputed AO (one channel, e.g. screenSpaceAO) over the pixels shaded, in the same
    // pixel coordinates as the G-buffer; it takes precedence over ray-traced AO.
    const OIIO::ImageBuf* ambientOcclusion = nullptr;
    // A photograph (RGB, the frame's pixels) the result is composited over ("over": RGB +
    // plate × (1 − A), A = 1): objects and their caught shadows onto the real place.
    const OIIO::ImageBuf* plate = nullptr;
    // Light probes (probes.h): indirect diffuse light, diffuseAlbedo × E / π with E
    // interpolated from the probes around each point, times AO when AO is on. Environments'
    // diffuse light then comes through the probes; their specular light stays the IBL's.
    const ProbeVolume* probes = nullptr;
    // The scene's closest hits (usually the same RayCaster as `visibility`): a shadow catcher
    // then counts the light the objects bounce onto it (params.catcherBounceSamples).
    const RayCaster* scene = nullptr;
    // Optional, for strips of one frame shaded in order: the previous strip's estimates in the
    // rows both hold (read), this strip's for the next (written). Null: every row is traced.
    EstimateCarry* carry = nullptr;
    // Optional: called as each pixel of the roi is shaded, from whichever thread shaded it,
    // with how many are done and of how many (a progress line for long work; it must be
    // thread-safe, and no pixel depends on it).
    const std::function<void(long long done, long long total)>* shaded = nullptr;
};

} // namespace dhdr
