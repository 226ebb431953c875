#include "integrator/background.h"

#include <algorithm>
#include <dhdr/deferred/lights/environment.h>

namespace dhdr {

Background::Background(const LightingParams& params, const ShadeSetup& setup,
                       const gbuffer::CameraInfo& camera, OIIO::ROI frame,
                       const OIIO::ImageBuf* plate)
    : m_colour(params.background), m_sky(setup.sky),
      m_skyBehind(setup.sky && params.environmentBackground), m_plate(plate),
      m_plated(plate || (params.plateEnvironment && setup.sky)), m_frame(frame),
      m_ndcToWorld(glm::inverse(camera.worldToNDC)) {}

// The view ray from the inverse of worldToNDC: the points of the near and far planes.
glm::vec3 Background::skyRadiance(int x, int y) const {
    const int px = x - m_frame.xbegin, py = y - m_frame.ybegin;
    const int frameWidth = m_frame.width(), frameHeight = m_frame.height();
    const double nx = (px + 0.5) / frameWidth * 2.0 - 1.0;
    const double ny = 1.0 - (py + 0.5) / frameHeight * 2.0;
    const glm::dvec4 a = m_ndcToWorld * glm::dvec4(nx, ny, -1.0, 1.0);
    const glm::dvec4 b = m_ndcToWorld * glm::dvec4(nx, ny, 1.0, 1.0);
    const glm::vec3 d(glm::normalize(glm::dvec3(b) / b.w - glm::dvec3(a) / a.w));
    return environmentRadiance(*m_sky, d);
}

void Background::uncovered(float* out, int x, int y) const {
    std::copy(m_colour, m_colour + 4, out);
    if (m_skyBehind) {
        const glm::vec3 L = skyRadiance(x, y);
        out[0] = L.r;
        out[1] = L.g;
        out[2] = L.b;
        out[3] = 1.0f;
    }
}

void Background::behind(float* out, float alpha, const glm::vec3& through, int x, int y) const {
    if (m_skyBehind) {
        const glm::vec3 L = skyRadiance(x, y);
        for (int c = 0; c < 3; ++c)
            out[c] += through[c] * L[c];
        out[3] = 1.0f;
    } else {
        for (int c = 0; c < 3; ++c)
            out[c] += through[c] * m_colour[c];
        out[3] += (1.0f - alpha) * m_colour[3];
    }
}

void Background::overPlate(float* out, int x, int y) const {
    glm::vec3 behind(0.0f);
    if (m_plate) {
        for (int c = 0; c < 3; ++c)
            behind[c] = m_plate->getchannel(x, y, 0, std::min(c, m_plate->nchannels() - 1));
    } else {
        behind = skyRadiance(x, y);
    }
    const float a = out[3];
    for (int c = 0; c < 3; ++c)
        out[c] += behind[c] * (1.0f - a);
    out[3] = 1.0f;
}

} // namespace dhdr
