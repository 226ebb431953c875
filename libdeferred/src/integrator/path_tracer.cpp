#include "integrator/path_tracer.h"

#include <algorithm>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/geometry/surface.h>
#include <dhdr/deferred/lights/environment.h>
#include <dhdr/deferred/lights/light.h>

namespace dhdr {

struct PathTracer::Vertex {
    PbrSurface surface;
    glm::vec3 P, N, V;
    SurfacePoint origin;
    float specularChance = 0.5f; // the share of BRDF samples drawn from the GGX lobe
    float coatChance = 0.0f;     // the share drawn first from a clearcoat's lobe
};

// Counter-based numbers: the i-th of a path is a hash of its seed and i, so that a path's
// numbers do not depend on what other paths, pixels or threads drew.
class PathTracer::Random {
public:
    explicit Random(std::uint64_t seed) : m_seed(seed) {}
    float next() { return unitFloat(mixBits(m_seed + 0x9e3779b97f4a7c15ull * ++m_index)); }
    glm::vec2 next2() {
        const float a = next();
        return {a, next()};
    }

private:
    std::uint64_t m_seed, m_index = 0;
};

namespace {

// Transparent surfaces a path's ray may pass before it stops at the next one.
constexpr int kPathRayLayers = 16;

// Veach's power heuristic for one sample of each of two techniques.
float powerHeuristic(float own, float other) {
    const float a = own * own, b = other * other;
    return a + b > 0.0f ? a / (a + b) : 0.0f;
}

// Lights that a BRDF-sampled ray can meet, and whose light samples are therefore weighed
// against it: the environment and a sun's disk. Area lights are not in the traced scene, and
// emissive meshes count through their light samples alone.
bool reachableByRays(const Light& light) {
    return isEnvironment(light) || hasSunDisk(light);
}

// The GGX lobe's share of BRDF samples: its Fresnel reflectance at N·V against the diffuse
// layer's albedo, kept within [0.1, 0.9] where both layers reflect.
float specularChance(const PbrSurface& s, float NdotV) {
    const float specular = luminance(s.fresnel(NdotV));
    const float diffuse = luminance(s.diffuseColor()) * (1.0f - specular);
    if (!(diffuse > 0.0f)) return 1.0f;
    if (!(specular > 0.0f)) return 0.0f;
    return std::clamp(specular / (specular + diffuse), 0.1f, 0.9f);
}

// A clearcoat's share of BRDF samples: its layer weight towards V, within [0.1, 0.5].
float coatChance(const PbrSurface& s, const glm::vec3& V) {
    return s.coated() ? std::clamp(s.coatBlend(V), 0.1f, 0.5f) : 0.0f;
}

// The density of reflecting V about GGX visible normals of roughness α around N, towards wi.
float ggxReflectionPdf(const glm::vec3& N, const glm::vec3& V, const glm::vec3& wi, float alpha) {
    const float NdotL = glm::dot(N, wi), NdotV = glm::dot(N, V);
    if (!(NdotL > 0.0f) || !(NdotV > 0.0f)) return 0.0f;
    const float NdotH = std::max(glm::dot(N, glm::normalize(wi + V)), 0.0f);
    return ggxVisibleNormalReflectionPdf(NdotV, NdotH, alpha);
}

// The density of the BRDF sampling below for direction wi: the mixture of the GGX visible-
// normal reflection and the cosine, under a clearcoat's lobe (coatChance) where there is one.
float bsdfPdf(const PbrSurface& s, const glm::vec3& N, const glm::vec3& V, const glm::vec3& wi,
              float specularChance, float coat) {
    const float NdotL = glm::dot(N, wi), NdotV = glm::dot(N, V);
    float base = 0.0f;
    if (NdotL > 0.0f && NdotV > 0.0f) {
        const glm::vec3 H = glm::normalize(wi + V);
        const float NdotH = std::max(glm::dot(N, H), 0.0f);
        base = specularChance * ggxVisibleNormalReflectionPdf(NdotV, NdotH, s.alpha()) +
               (1.0f - specularChance) * NdotL / kPi;
    }
    if (!(coat > 0.0f)) return base;
    return coat * ggxReflectionPdf(s.coat.normal, V, wi, s.coatLobe().alpha()) +
           (1.0f - coat) * base;
}

// Reflects V about a GGX visible normal of roughness α around the unit normal N (u in [0, 1)²).
glm::vec3 sampleGgxReflection(const glm::vec3& N, const glm::vec3& V, float alpha, glm::vec2 u) {
    glm::vec3 t, b;
    orthonormalBasis(N, t, b);
    const glm::vec3 h = sampleGgxVisibleNormal(
        glm::vec3(glm::dot(V, t), glm::dot(V, b), std::max(glm::dot(N, V), 1e-6f)), alpha, u);
    const glm::vec3 H = glm::normalize(h.x * t + h.y * b + h.z * N);
    return 2.0f * glm::dot(V, H) * H - V;
}

} // namespace

PathTracer::PathTracer(const std::vector<Light>& lights, const RayCaster& caster,
                       const PathTracerOptions& options)
    : m_lights(lights), m_infinite(infiniteLights(lights)), m_caster(caster), m_options(options) {
    m_emissionAtHits = std::none_of(lights.begin(), lights.end(), isEmissiveMesh);
}

glm::vec3 PathTracer::sampleLights(const Vertex& v, Random& random, long long& rays) const {
    glm::vec3 L(0.0f);
    for (const Light& light : m_lights) {
        // Ambient light reaches a point from everywhere: BRDF-sampled rays find it.
        if (isAmbient(light)) continue;
        const glm::vec2 u = random.next2(); // drawn for every light: a fixed layout
        LightLiSample s = sampleLi(light, v.P, u);
        if (!(s.pdf > 0.0f)) continue;
        const float cosTheta = glm::dot(v.N, s.wi);
        if (!(cosTheta > 0.0f) || !leavesSurface(v.origin, s.wi)) continue;
        const glm::vec3 f = evaluateBrdf(v.surface, v.N, v.V, s.wi) * cosTheta;
        if (f == glm::vec3(0.0f)) continue;
        // The environment as the BRDF-sampled rays see it (full resolution), so that both
        // techniques estimate the same integral.
        if (isEnvironment(light)) s.L = environmentRadiance(light, s.wi);
        const float weight = !s.delta && reachableByRays(light)
                                 ? powerHeuristic(s.pdf, bsdfPdf(v.surface, v.N, v.V, s.wi,
                                                                 v.specularChance, v.coatChance))
                                 : 1.0f;
        if (!(weight > 0.0f) || s.L == glm::vec3(0.0f)) continue;
        ++rays;
        const float visible = m_caster.transmittance(offsetRayOrigin(v.origin, s.wi), s.wi,
                                                     s.distance * (1.0f - kShadowRayShortening));
        L += f * s.L * (visible * weight / s.pdf);
    }
    return L;
}

glm::vec3 PathTracer::lightsAtInfinity(const glm::vec3& wi, float bsdf) const {
    glm::vec3 L(0.0f);
    for (const std::uint32_t i : m_infinite) {
        const Light& light = m_lights[i];
        if (isAmbient(light)) {
            L += light.color * light.intensity;
        } else if (isEnvironment(light) && light.ibl) {
            glm::vec3 table;
            const float pdf = light.ibl->sampler.empty()
                                  ? 0.0f
                                  : light.ibl->sampler.lookup(intoEnvironment(light, wi), table);
            L += environmentRadiance(light, wi) * powerHeuristic(bsdf, pdf);
        } else if (hasSunDisk(light)) {
            if (glm::dot(wi, -light.direction) < std::cos(0.5f * light.angle)) continue;
            // The disk's radiance and density: the same for every direction within it.
            const LightLiSample s = sampleLi(light, glm::vec3(0.0f), glm::vec2(0.5f));
            L += s.L * powerHeuristic(bsdf, s.pdf);
        }
    }
    return L;
}

glm::vec3 PathTracer::path(const LitPoint& first, Random& random, long long& rays) const {
    glm::vec3 L(0.0f), beta(1.0f);
    Vertex v{first.surface, first.P, first.N, first.V, first.origin};
    const Scene& scene = m_caster.scene();
    for (int depth = 0;; ++depth) {
        const float NdotV = glm::dot(v.N, v.V);
        if (!(NdotV > 0.0f)) break;
        v.specularChance = specularChance(v.surface, NdotV);
        v.coatChance = coatChance(v.surface, v.V);
        L += beta * sampleLights(v, random, rays);
        // The BRDF's own sample: the next vertex, or the lights at infinity on a miss.
        glm::vec3 t, b;
        orthonormalBasis(v.N, t, b);
        float lobe = random.next();
        const glm::vec2 u = random.next2();
        glm::vec3 wi;
        const bool coat = lobe < v.coatChance;
        if (v.coatChance > 0.0f && !coat) lobe = (lobe - v.coatChance) / (1.0f - v.coatChance);
        if (coat) {
            wi = sampleGgxReflection(v.surface.coat.normal, v.V, v.surface.coatLobe().alpha(), u);
        } else if (lobe < v.specularChance) {
            const glm::vec3 h = sampleGgxVisibleNormal(
                glm::vec3(glm::dot(v.V, t), glm::dot(v.V, b), NdotV), v.surface.alpha(), u);
            const glm::vec3 H = glm::normalize(h.x * t + h.y * b + h.z * v.N);
            wi = 2.0f * glm::dot(v.V, H) * H - v.V;
        } else {
            const glm::vec3 c = cosineHemisphere(u);
            wi = glm::normalize(c.x * t + c.y * b + c.z * v.N);
        }
        const float cosTheta = glm::dot(v.N, wi);
        if (!(cosTheta > 0.0f) || !(glm::dot(v.origin.Ng, wi) > 0.0f)) break;
        const float pdf = bsdfPdf(v.surface, v.N, v.V, wi, v.specularChance, v.coatChance);
        if (!(pdf > 0.0f)) break;
        beta *= evaluateBrdf(v.surface, v.N, v.V, wi) * (cosTheta / pdf);
        if (beta == glm::vec3(0.0f)) break;
        const Ray ray{glm::dvec3(offsetRayOrigin(v.origin, wi)), glm::dvec3(wi)};
        RayHit hit = m_caster.intersect(ray);
        ++rays;
        // Through Mask cut-outs, and through a Blend surface of coverage α with probability
        // 1 − α, as shadow rays pass it by transmittance 1 − α.
        for (int layer = 0; hit.hit && hit.mesh >= 0 && layer < kPathRayLayers; ++layer) {
            const SurfaceCoverage c =
                surfaceCoverage(scene, hit.mesh, hit.triangle, float(hit.u), float(hit.v));
            if (c.present && (c.alpha >= 1.0f || random.next() < c.alpha)) break;
            hit = m_caster.intersect(ray, hit.t * (1.0 + 1e-6) + 1e-6);
            ++rays;
        }
        if (!hit.hit) {
            L += beta * lightsAtInfinity(wi, pdf);
            break;
        }
        const SurfaceSample s = surfaceAt(scene, ray, hit);
        // Inside a closed mesh: no light.
        if (s.backFace) break;
        if (m_emissionAtHits) L += beta * s.emission;
        if (depth == m_options.bounces) break;
        // Russian roulette from the third vertex on (pbrt-v4): a path whose throughput has
        // fallen below 1 ends with probability 1 − max(β), the survivors weigh 1 / (1 − q).
        const float most = std::max({beta.r, beta.g, beta.b});
        if (depth >= 1 && most < 1.0f) {
            const float q = std::max(0.0f, 1.0f - most);
            if (random.next() < q) break;
            beta /= 1.0f - q;
        }
        const PbrSurface surface = s.pbr(m_options.diffuse);
        const glm::vec3 P(s.position);
        v = Vertex{surface, P, glm::vec3(s.normal), -wi,
                   SurfacePoint{P, glm::vec3(s.geometric), float(s.positionError)}};
    }
    return L;
}

glm::vec3 PathTracer::radiance(const LitPoint& first, int x, int y, int k, long long* rays) const {
    glm::dvec3 sum(0.0);
    long long traced = 0;
    for (int i = 0; i < m_options.samples; ++i) {
        Random random(sampleSeed(x, y, i, streamOf(SampleStream::Path, k)));
        sum += glm::dvec3(path(first, random, traced));
    }
    if (rays) *rays += traced;
    return glm::vec3(sum / double(std::max(m_options.samples, 1)));
}

} // namespace dhdr
