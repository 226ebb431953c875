// What shows behind the surfaces (as Cycles' shade_background.h): params.background, or the
// first environment as the camera sees it, where there is no surface and behind a deep pixel's
// samples; and the plate (a photograph of the frame, or the environment) under everything.
#pragma once

#include "integrator/shade_setup.h"

#include <OpenImageIO/imagebuf.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <glm/glm.hpp>

namespace dhdr {

class Background {
public:
    // Behind the pixels of `frame` (the whole frame, of which the G-buffer may be a strip)
    // seen by `camera`; `plate` optional.
    Background(const LightingParams& params, const ShadeSetup& setup,
               const gbuffer::CameraInfo& camera, OIIO::ROI frame, const OIIO::ImageBuf* plate);

    // The RGBA of pixel (x, y) where the G-buffer has no surface.
    void uncovered(float* out, int x, int y) const;
    // Added behind a deep pixel's samples composited to RGBA `out` of alpha `alpha`, which
    // pass `through` of it per channel (1 − alpha unless light passes a sample).
    void behind(float* out, float alpha, const glm::vec3& through, int x, int y) const;
    // Whether everything is composited over a plate (overPlate).
    bool plated() const { return m_plated; }
    // `out` composited over the plate: RGB + plate × (1 − A), A = 1.
    void overPlate(float* out, int x, int y) const;

private:
    // The environment along the view ray through the centre of pixel (x, y).
    glm::vec3 skyRadiance(int x, int y) const;

    const float* m_colour; // params.background
    const Light* m_sky;
    bool m_skyBehind; // the sky instead of m_colour (params.environmentBackground)
    const OIIO::ImageBuf* m_plate;
    bool m_plated;
    OIIO::ROI m_frame;
    glm::dmat4 m_ndcToWorld;
};

} // namespace dhdr
