// The deferred lighting pass: a G-buffer and a list of lights in, linear HDR radiance out.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <dhdr/deferred/lights.h>
#include <string>
#include <vector>

namespace dhdr {

struct LightingParams {
    // Evaluate every light at every pixel instead of only those whose screen rectangle
    // covers the pixel's tile: the reference the culled pass must match.
    bool bruteForce = false;
    // Side of the square tiles that per-tile light lists are built for, in pixels.
    int tileSize = 16;
    // RGBA written where the G-buffer has no surface (A = 0).
    float background[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    // G-buffer channels copied into the output after R, G, B, A (e.g. "Z", "N.X"...).
    std::vector<std::string> passThrough;
    // The whole frame, when the G-buffer given is a strip of its rows (dhdr-light streams
    // frames strip by strip); undefined: the G-buffer's own pixels are the frame. Tiles are
    // laid over the frame, so a pixel's result does not depend on how the frame is cut.
    OIIO::ROI frame;
};

struct LightingStats {
    // Lights considered, summed over covered pixels: those in the pixel's tile list whose
    // depth slice matches (every light with bruteForce).
    long long lightEvaluations = 0;
    // Of those, the lights whose range actually reaches the pixel's surface point.
    long long lightsReaching = 0;
    long long coveredPixels = 0;
    // Entries of all the tile lists.
    long long tileListEntries = 0;
};

// Shades every covered pixel of `gbuffer` with Lambert + Cook-Torrance (brdf.h) under
// `lights`, adds emission, and writes R, G, B, A (then `passThrough`) as float pixels into
// `dst`, whose spec keeps `gbuffer`'s metadata. Each light is evaluated only at the pixels of
// the tiles and depth slices its bound reaches (light_culling.h), in the order of `lights`,
// so the culled and brute-force results agree to rounding. Errors (a missing channel, no
// camera in the header) are reported on `dst`. `dst` is reused when it already holds float
// pixels of the right size and channels (the previous strip).
bool shadeGBuffer(OIIO::ImageBuf& dst, const OIIO::ImageBuf& gbuffer,
                  const std::vector<Light>& lights, const LightingParams& params = {},
                  LightingStats* stats = nullptr, int nthreads = 0);

} // namespace dhdr
