// The surface samples of a G-buffer, as the lighting pass reads them: a small view that
// hands back the samples of a pixel (one for a flat G-buffer, front to back for a deep one).
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <cstdint>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/core/visibility.h>
#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <limits>
#include <optional>

namespace dhdr {

struct ShadingPoint {
    glm::vec3 P{0.0f}; // world space
    glm::vec3 N{0.0f}; // unit shading normal, facing the camera
    // Where secondary rays leave from: P, the geometric normal (facing the camera) and P's
    // error bound, from Ng and Perr, or N and fallbackPositionError where the file has none.
    SurfacePoint origin;
    glm::vec3 V{0.0f}; // unit, towards the eye
    PbrSurface surface;
    glm::vec3 emission{0.0f};
    // The material's occlusion (the occlusion channel; 1 without one): it scales ambient,
    // environment and indirect light, never direct light (glTF 2.0 §3.9.3).
    float occlusion = 1.0f;
    // N was no direction (zero, NaN, ±Inf) and was replaced (GBufferView::at).
    bool normalRepaired = false;
    float coverage = 0.0f; // the pixel's A
    // KHR_materials_volume: what the medium behind the sample lets through to the next one.
    glm::vec3 attenuation{1.0f};
    float depth = 0.0f; // Z
};

// What every pass over a G-buffer needs first: its channels, its camera and its pixels as
// float in memory (the G-buffer itself when it already is, else `floatCopy`).
struct GBufferPixels {
    gbuffer::Layout layout;
    gbuffer::CameraInfo camera;
    OIIO::ImageBuf floatCopy;
    const OIIO::ImageBuf* pixels = nullptr;
};

// Fills `out` from `gbuffer`; false with the error on `errors` (a missing channel, no camera).
bool openGBuffer(const OIIO::ImageBuf& gbuffer, GBufferPixels& out, OIIO::ImageBuf& errors);

// Reads shading points out of a G-buffer held in memory as float: a flat one (e.g. one strip
// of a frame), or a deep one with several samples a pixel.
class GBufferView {
public:
    // Its surfaces' diffuse layer is `diffuse`'s (the G-buffer does not say).
    GBufferView(const OIIO::ImageBuf& gbuffer, const gbuffer::Layout& layout,
                const gbuffer::CameraInfo& camera, DiffuseModel diffuse = DiffuseModel::Lambert)
        : m_data(static_cast<const float*>(gbuffer.localpixels())),
          m_nch(size_t(gbuffer.nchannels())), m_x0(gbuffer.spec().x), m_y0(gbuffer.spec().y),
          m_width(gbuffer.spec().width), m_layout(layout), m_camera(camera), m_diffuse(diffuse) {}
    GBufferView(const DeepGBuffer& gbuffer, const gbuffer::Layout& layout,
                const gbuffer::CameraInfo& camera, DiffuseModel diffuse = DiffuseModel::Lambert)
        : m_data(gbuffer.values.data()), m_nch(size_t(gbuffer.spec.nchannels)),
          m_x0(gbuffer.spec.x), m_y0(gbuffer.spec.y), m_width(gbuffer.spec.width),
          m_first(gbuffer.first.data()), m_layout(layout), m_camera(camera), m_diffuse(diffuse) {}

    bool deep() const { return m_first != nullptr; }

    // Surface samples of pixel (x, y) in image coordinates, front to back: 0 on the
    // background.
    int samples(int x, int y) const {
        if (m_first) {
            const size_t p = pixel(x, y);
            return int(m_first[p + 1] - m_first[p]);
        }
        return channels(x, y)[m_layout.coverage] > 0.0f ? 1 : 0;
    }

    ShadingPoint at(int x, int y, int sample = 0) const {
        const float* g = channels(x, y, sample);
        ShadingPoint s;
        s.P = glm::vec3(g[m_layout.position], g[m_layout.position + 1], g[m_layout.position + 2]);
        s.V = glm::vec3(m_camera.toEye(s.P));
        std::optional<glm::vec3> Ng;
        if (m_layout.geometricNormal >= 0) {
            const glm::vec3 n(g[m_layout.geometricNormal], g[m_layout.geometricNormal + 1],
                              g[m_layout.geometricNormal + 2]);
            const float len = glm::length(n);
            if (len > 0.5f && len < 2.0f) Ng = n / len;
        }
        const std::optional<glm::vec3> N = unitDirection(
            glm::vec3(g[m_layout.normal], g[m_layout.normal + 1], g[m_layout.normal + 2]));
        // A normal of zero length (NaN or ±Inf read as 0) or none at all is no direction: the
        // triangle's, else the one facing the eye (docs/gbuffer.md), counted by the caller.
        s.normalRepaired = !N;
        s.N = N ? *N : Ng ? *Ng : s.V;
        s.origin.P = s.P;
        s.origin.Ng = Ng ? *Ng : s.N;
        s.origin.error = m_layout.positionError >= 0 ? g[m_layout.positionError] : -1.0f;
        if (!(s.origin.error >= 0.0f && s.origin.error < INFINITY))
            s.origin.error = fallbackPositionError(s.P, glm::vec3(m_camera.position));
        if (m_layout.lift >= 0) readLift(g, s.origin);
        s.origin.N = s.N;
        s.surface.baseColor =
            glm::vec3(g[m_layout.albedo], g[m_layout.albedo + 1], g[m_layout.albedo + 2]);
        s.surface.roughness = std::clamp(g[m_layout.roughness], 0.0f, 1.0f);
        s.surface.metallic = std::clamp(g[m_layout.metallic], 0.0f, 1.0f);
        s.surface.diffuse = m_diffuse;
        if (m_layout.specular >= 0 && m_layout.specularWeight >= 0) {
            for (int c = 0; c < 3; ++c)
                s.surface.dielectricF0[c] = unitOr(g[m_layout.specular + c], 0.04f);
            s.surface.dielectricF90 = unitOr(g[m_layout.specularWeight], 1.0f);
        }
        if (m_layout.emission >= 0)
            s.emission =
                glm::vec3(g[m_layout.emission], g[m_layout.emission + 1], g[m_layout.emission + 2]);
        if (m_layout.clearcoat >= 0 && m_layout.clearcoatRoughness >= 0 &&
            m_layout.clearcoatNormal >= 0)
            readCoat(g, s);
        if (m_layout.sheen >= 0 && m_layout.sheenRoughness >= 0)
            s.surface.sheen = {glm::vec3(unitOr(g[m_layout.sheen], 0.0f),
                                         unitOr(g[m_layout.sheen + 1], 0.0f),
                                         unitOr(g[m_layout.sheen + 2], 0.0f)),
                               unitOr(g[m_layout.sheenRoughness], 0.0f)};
        if (m_layout.transmission >= 0)
            s.surface.transmission = unitOr(g[m_layout.transmission], 0.0f);
        if (m_layout.attenuation >= 0)
            for (int c = 0; c < 3; ++c)
                s.attenuation[c] = unitOr(g[m_layout.attenuation + c], 1.0f);
        if (m_layout.occlusion >= 0) {
            const float o = g[m_layout.occlusion];
            s.occlusion = std::isnan(o) ? 1.0f : std::clamp(o, 0.0f, 1.0f);
        }
        s.coverage = g[m_layout.coverage];
        s.depth = g[m_layout.depth];
        return s;
    }

    // All channels of a sample of pixel (x, y) (of the pixel, flat), for passing through.
    const float* channels(int x, int y, int sample = 0) const {
        if (m_first) return m_data + (size_t(m_first[pixel(x, y)]) + size_t(sample)) * m_nch;
        return m_data + pixel(x, y) * m_nch;
    }
    // Whether the pixels may hold several rays (a deep G-buffer with sample.id and
    // sample.weight, docs/gbuffer.md): each ray's samples composite over each other, the rays
    // side by side, each its share of the pixel.
    bool severalRays() const {
        return m_first && m_layout.sampleId >= 0 && m_layout.sampleWeight >= 0;
    }
    // Sample k's ray (severalRays; any other value a file holds is ray 0) and the ray's share
    // of the pixel, in [0, 1] (NaN: 0).
    std::uint32_t ray(int x, int y, int k) const {
        const float id = channels(x, y, k)[m_layout.sampleId];
        return id >= 0.0f && id < 4294967040.0f ? std::uint32_t(id) : 0u;
    }
    float rayWeight(int x, int y, int k) const {
        return unitOr(channels(x, y, k)[m_layout.sampleWeight], 0.0f);
    }
    // The index of a sample among all of a deep G-buffer's (for per-sample outputs).
    size_t sampleIndex(int x, int y, int sample) const {
        return size_t(m_first[pixel(x, y)]) + size_t(sample);
    }

private:
    // Plift: finite, and never below the triangle (a half's rounding, or a file another
    // program wrote); a point whose Ng the file does not give is not lifted.
    void readLift(const float* g, SurfacePoint& o) const {
        const glm::vec3 lift(g[m_layout.lift], g[m_layout.lift + 1], g[m_layout.lift + 2]);
        if (m_layout.geometricNormal < 0 || !std::isfinite(lift.x + lift.y + lift.z)) return;
        const float below = glm::dot(lift, o.Ng);
        o.lift = below < 0.0f ? lift - below * o.Ng : lift;
    }

    // KHR_materials_clearcoat's channels; the coat sits over the emission too (its
    // "Emission" section: emission × (1 − clearcoat · clearcoat_fresnel)).
    void readCoat(const float* g, ShadingPoint& s) const {
        const float weight = unitOr(g[m_layout.clearcoat], 0.0f);
        const std::optional<glm::vec3> Nc =
            unitDirection(glm::vec3(g[m_layout.clearcoatNormal], g[m_layout.clearcoatNormal + 1],
                                    g[m_layout.clearcoatNormal + 2]));
        if (!(weight > 0.0f)) return;
        s.surface.coat = {weight, unitOr(g[m_layout.clearcoatRoughness], 0.0f), Nc ? *Nc : s.N};
        s.emission *= 1.0f - s.surface.coatBlend(s.V);
    }

    // `v` scaled to unit length, when it has a direction: finite, not zero. Components whose
    // squares would overflow or vanish are divided by the largest first.
    static std::optional<glm::vec3> unitDirection(glm::vec3 v) {
        const float m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
        if (!(m > 0.0f && m <= std::numeric_limits<float>::max())) return std::nullopt;
        const float squared = glm::dot(v, v);
        if (squared >= std::numeric_limits<float>::min() && squared < INFINITY)
            return glm::normalize(v);
        return glm::normalize(v / m);
    }

    // `v` in [0, 1], `fallback` for NaN.
    static float unitOr(float v, float fallback) {
        return std::isnan(v) ? fallback : std::clamp(v, 0.0f, 1.0f);
    }

    size_t pixel(int x, int y) const {
        return size_t(y - m_y0) * size_t(m_width) + size_t(x - m_x0);
    }

    const float* m_data;
    size_t m_nch;
    int m_x0, m_y0, m_width;
    const std::uint32_t* m_first = nullptr; // deep: each pixel's first sample
    const gbuffer::Layout& m_layout;
    const gbuffer::CameraInfo& m_camera;
    DiffuseModel m_diffuse;
};

} // namespace dhdr
