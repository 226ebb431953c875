// The deferred lighting pass: a G-buffer and a list of lights in, linear HDR radiance out.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <dhdr/deferred/integrator/lighting_inputs.h>
#include <dhdr/deferred/integrator/lighting_params.h>
#include <dhdr/deferred/integrator/lighting_stats.h>
#include <vector>

namespace dhdr {

struct DeepGBuffer;

// Shades every covered pixel of `roi` of `gbuffer` (undefined: all of it) and writes R, G, B,
// A (then AO with writeAO, then `passThrough`) as float pixels into `dst`, whose spec keeps
// `gbuffer`'s metadata. For each surface point (shading_point.h):
//   Lo = emission + Σ_lights V_i · L_i + AO · Σ_ambient L_a
// with L_i the light's exact unshadowed reflection (Lambert + Cook-Torrance, brdf.h; area
// lights lights/area.h; environments the split sum of ibl.h), V_i its visibility (shadows.h; 1
// without a Visibility) and AO the ambient occlusion (ambient_occlusion.h). AO multiplies only
// the ambient terms (ambient lights, environments' diffuse light; their specular light by
// specular occlusion): punctual and area lights have their shadows. Pixels of the G-buffer's
// shadow catcher (gbuffer::kShadowCatcher) get RGB 0 and A = 1 − shadowed / unshadowed
// luminance; with a plate, every pixel is then composited over it. Each light is evaluated only at
// the pixels of the tiles and depth slices its bound reaches (light_culling.h), in the order of the
// lights, so culled and brute-force results agree to rounding; every sample sequence depends only
// on the pixel and the light, so results do not depend on `nthreads` or on the strip. Errors (a
// missing channel, no camera in the header) are reported on `dst`. `dst` is reused when it already
// holds float pixels of the right size and channels (the previous strip).
bool shadeGBuffer(OIIO::ImageBuf& dst, const OIIO::ImageBuf& gbuffer, const LightingInputs& inputs,
                  const LightingParams& params = {}, OIIO::ROI roi = {}, int nthreads = 0,
                  LightingStats* stats = nullptr);

// A deep G-buffer (deep_gbuffer.h), its whole frame or a band of its rows (params.frame, as for
// flat strips; the same pixels either way): every sample is lit as an opaque surface
// would be (the same tile lists, bounded by all samples' depths; shadow and AO rays from each;
// its own sample sequences, sample 0's those of a flat pixel) and the samples are composited
// front to back, premultiplied "over", into the flat RGBA of `dst`; what is left uncovered
// shows the background (params.background or the environment) and the plate. With
// `sampleRGBA`, each sample's own premultiplied RGBA (4 floats a sample, in the order of
// gbuffer.values) for a deep output. An AO image (one value a pixel) is an error here.
bool shadeGBuffer(OIIO::ImageBuf& dst, const DeepGBuffer& gbuffer, const LightingInputs& inputs,
                  const LightingParams& params = {}, OIIO::ROI roi = {}, int nthreads = 0,
                  LightingStats* stats = nullptr, std::vector<float>* sampleRGBA = nullptr);

} // namespace dhdr
