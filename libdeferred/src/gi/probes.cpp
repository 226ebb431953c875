// Looking up a probe volume: the octahedral maps and the interpolation between probes.
#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/core/octahedral.h>
#include <dhdr/deferred/core/visibility.h>
#include <dhdr/deferred/gi/probes.h>

namespace dhdr {

namespace {

// Bilinear in a bordered (n + 2)² map at direction d: the interior spans texels 1 … n, texel
// centres at half-integers, and the border makes the taps next to an edge land on the texel
// across it.
template <class T>
T octLookup(const T* map, int n, const glm::vec3& d) {
    const glm::vec2 e = octEncode(d);
    // Interior texel k covers [k, k + 1) in texel units, offset by the border.
    const float fx = (e.x * 0.5f + 0.5f) * float(n) + 0.5f,
                fy = (e.y * 0.5f + 0.5f) * float(n) + 0.5f;
    const int x0 = std::clamp(int(std::floor(fx)), 0, n),
              y0 = std::clamp(int(std::floor(fy)), 0, n);
    const float ax = std::clamp(fx - float(x0), 0.0f, 1.0f),
                ay = std::clamp(fy - float(y0), 0.0f, 1.0f);
    const int w = n + 2;
    auto at = [&](int x, int y) { return map[y * w + x]; };
    return (at(x0, y0) * (1.0f - ax) + at(x0 + 1, y0) * ax) * (1.0f - ay) +
           (at(x0, y0 + 1) * (1.0f - ax) + at(x0 + 1, y0 + 1) * ax) * ay;
}

} // namespace

glm::vec3 sphericalFibonacci(int i, int n) {
    // Keinert et al. 2015, "Spherical Fibonacci Mapping", eq. 2: φ = 2π i / Φ, cos θ = 1 − (2i +
    // 1)/n.
    const double golden = (1.0 + std::sqrt(5.0)) / 2.0;
    const double phi =
        2.0 * 3.14159265358979323846 * (double(i) / golden - std::floor(double(i) / golden));
    const double cosTheta = 1.0 - (2.0 * i + 1.0) / n;
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    return glm::vec3(glm::dvec3(std::cos(phi) * sinTheta, std::sin(phi) * sinTheta, cosTheta));
}

glm::vec3 ProbeVolume::irradianceAt(int p, const glm::vec3& n) const {
    const int w = kIrradianceTexels + 2;
    return octLookup(&irradiance[size_t(p) * size_t(w * w)], kIrradianceTexels, n);
}

glm::vec2 ProbeVolume::distanceAt(int p, const glm::vec3& d) const {
    const int w = kDistanceTexels + 2;
    return octLookup(&distance[size_t(p) * size_t(w * w)], kDistanceTexels, d);
}

glm::vec3 ProbeVolume::irradianceAt(const glm::vec3& P, const glm::vec3& N, const glm::vec3& V,
                                    const Visibility* scene) const {
    if (positions.empty()) return glm::vec3(0.0f);
    const float minSpacing = float(std::min({spacing.x, spacing.y, spacing.z}));
    // DDGI §5.2: the point is moved off the surface along the normal and towards the eye, so
    // that the visibility test does not self-shadow on the surface it shades.
    const glm::vec3 biased = P + (N * normalBias + V * viewBias) * minSpacing;
    // Surfaces on the scene's bounds (a room's walls) lie outside the grid's outer layers, a
    // quarter spacing (kProbeInset; half a spacing in files baked before), where the
    // irradiance differs from theirs (2.4 cm above the Cornell box's floor it is 7 % brighter
    // than on it). There it is extrapolated linearly from the grid: E(biased) = 2 E(Q) − E(Q'),
    // Q the biased point clamped into the grid and Q' its mirror image about Q, each
    // interpolated as inside.
    const glm::dvec3 local = (glm::dvec3(biased) - origin) / spacing;
    glm::dvec3 inside = local, mirror = local;
    bool outside = false;
    for (int a = 0; a < 3; ++a) {
        const double top = double(std::max(counts[a] - 1, 0));
        if (top == 0.0 || (local[a] >= 0.0 && local[a] <= top)) continue;
        inside[a] = std::clamp(local[a], 0.0, top);
        // At most half a spacing beyond (the largest margin a grid has had), and within it.
        const double beyond = std::min(std::abs(local[a] - inside[a]), 0.5);
        mirror[a] = std::clamp(inside[a] + (inside[a] == 0.0 ? beyond : -beyond), 0.0, top);
        outside = true;
    }
    SeenFrom seen;
    if (!outside) return interpolate(P, N, biased, local, scene, seen);
    const glm::vec3 a = interpolate(P, N, biased, inside, scene, seen),
                    b = interpolate(P, N, biased, mirror, scene, seen);
    return glm::max(2.0f * a - b, glm::vec3(0.0f));
}

float ProbeVolume::chebyshev(int p, const glm::vec3& biased, float* traced, ShadowRay* ray) const {
    if (traced) *traced = 0.0f;
    const glm::vec3 fromProbe = biased - positions[size_t(p)];
    const float r = glm::length(fromProbe);
    if (!(r > 0.0f)) return 1.0f;
    // Chebyshev's bound on the chance that the probe sees the point (DDGI eq. 10): the probe's
    // mean and variance of distance in the point's direction against its distance; cubed to
    // sharpen, as RTXGI does.
    const glm::vec2 m = distanceAt(p, fromProbe / r);
    const float variance = std::abs(m.y - m.x * m.x);
    float chebyshev = 1.0f;
    if (r > m.x) {
        const float d = r - m.x, c = variance / (variance + d * d);
        chebyshev = c * c * c;
    }
    if (!traced) return chebyshev;
    // Moments that spread mix an edge's near distances with the far ones past it: their mean
    // may lie beyond a point the edge hides. There a ray decides (docs/gi.md "Shading").
    const float spread = std::sqrt(variance) / std::max(m.x, 1e-6f);
    const float t = std::clamp((spread - kProbeTracedSpread[0]) /
                                   (kProbeTracedSpread[1] - kProbeTracedSpread[0]),
                               0.0f, 1.0f);
    *traced = t * t * (3.0f - 2.0f * t);
    ray->origin = biased;
    ray->direction = -fromProbe / r;
    ray->tmax = r;
    return chebyshev;
}

float ProbeVolume::extrapolated(glm::ivec3 g, glm::ivec3 offset, const glm::vec3& N,
                                const glm::vec3& biased, glm::vec3& E) const {
    glm::vec3 sum(0.0f);
    float total = 0.0f;
    for (int a = 0; a < 3; ++a) {
        // Towards the cell's other corners along a: the neighbour in the cell, then the next.
        const int step = offset[a] ? -1 : 1;
        glm::ivec3 g1 = g, g2 = g;
        g1[a] += step;
        g2[a] += 2 * step;
        if (N[a] == 0.0f || g2[a] < 0 || g2[a] >= counts[a]) continue;
        const int p1 = index(g1), p2 = index(g2);
        if (states[size_t(p1)] == ProbeState::Off || states[size_t(p2)] == ProbeState::Off)
            continue;
        // The change along N is Σ N_a ∂E/∂x_a: each axis counts by its share N_a² of N. The
        // two probes lie on the point's open side, where the distance maps are reliable.
        const float w = N[a] * N[a] * chebyshev(p1, biased, nullptr, nullptr) *
                        chebyshev(p2, biased, nullptr, nullptr);
        if (w == 0.0f) continue;
        const glm::vec3 E1 = irradianceAt(p1, N), E2 = irradianceAt(p2, N);
        sum += w * glm::max(E1 + kProbeFillSlope * (E1 - E2), glm::vec3(0.0f));
        total += w;
    }
    if (total > 0.0f) E = sum / total;
    return total;
}

void ProbeVolume::cornerVisibilities(glm::ivec3 base, const double trilinear[8],
                                     const glm::vec3& biased, const Visibility* scene,
                                     SeenFrom& seen, float visible[8]) const {
    // The rays go as one stream of single rays: in packets these diverging rays were slower
    // (the 1080p frame 4.0 s against 3.75). A probe `seen` holds was looked at from this
    // point already, for the other cell of a wall's extrapolation.
    float traced[8] = {}, open[8] = {};
    std::fill_n(visible, 8, 0.0f);
    ShadowRay rays[8];
    int rayOf[8], known[8], n = 0;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::ivec3 offset(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
        const int p = index(glm::min(base + offset, counts - 1));
        rayOf[corner] = known[corner] = -1;
        if (trilinear[corner] == 0.0 || states[size_t(p)] == ProbeState::Off) continue;
        for (int i = 0; i < seen.count && known[corner] < 0; ++i)
            if (seen.probe[i] == p) known[corner] = i;
        if (known[corner] >= 0) continue;
        visible[corner] = chebyshev(p, biased, scene ? &traced[corner] : nullptr, &rays[n]);
        if (traced[corner] > 0.0f) rayOf[corner] = n++;
    }
    if (n > 0) scene->test(rays, size_t(n), open);
    for (int corner = 0; corner < 8; ++corner) {
        const glm::ivec3 offset(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
        const int p = index(glm::min(base + offset, counts - 1));
        if (known[corner] >= 0) {
            visible[corner] = seen.visible[known[corner]];
            continue;
        }
        if (rayOf[corner] >= 0)
            visible[corner] =
                (1.0f - traced[corner]) * visible[corner] + traced[corner] * open[rayOf[corner]];
        if (trilinear[corner] == 0.0 || states[size_t(p)] == ProbeState::Off ||
            seen.count == SeenFrom::kSize)
            continue;
        seen.probe[seen.count] = p;
        seen.visible[seen.count++] = visible[corner];
    }
}

glm::vec3 ProbeVolume::interpolate(const glm::vec3& P, const glm::vec3& N, const glm::vec3& biased,
                                   const glm::dvec3& local, const Visibility* scene,
                                   SeenFrom& seen) const {
    glm::ivec3 base;
    glm::vec3 alpha;
    for (int a = 0; a < 3; ++a) {
        const int cells = std::max(counts[a] - 1, 0);
        base[a] = std::clamp(int(std::floor(local[a])), 0, std::max(cells - 1, 0));
        alpha[a] = cells == 0 ? 0.0f : std::clamp(float(local[a] - base[a]), 0.0f, 1.0f);
    }
    // Trilinear weights of the grid points; a corner of weight 0 (on a clamped axis: the
    // surfaces beyond the outer layers) is not looked at.
    double trilinear[8];
    for (int corner = 0; corner < 8; ++corner) {
        trilinear[corner] = 1.0;
        for (int a = 0; a < 3; ++a)
            trilinear[corner] *= (corner >> a) & 1 ? alpha[a] : 1.0f - alpha[a];
    }
    float visible[8];
    cornerVisibilities(base, trilinear, biased, scene, seen, visible);
    glm::dvec3 sum(0.0);
    double total = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        if (trilinear[corner] == 0.0) continue;
        const glm::ivec3 offset(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
        const glm::ivec3 g = glm::min(base + offset, counts - 1);
        const int p = index(g);
        const float v = visible[corner];
        glm::dvec3 cornerSum(0.0);
        double cornerTotal = 0.0;
        if (states[size_t(p)] != ProbeState::Off) {
            // Back-face wrap: a probe behind the surface counts less, smoothly (DDGI eq. 9).
            const glm::vec3 toProbe = glm::normalize(positions[size_t(p)] - P);
            const float wrap = (glm::dot(toProbe, N) + 1.0f) * 0.5f;
            // A floor keeps a point seen by no probe from dividing by zero without letting a
            // hidden probe's light through.
            const float weight = std::max((wrap * wrap + 0.2f) * v, 1e-6f);
            cornerSum = glm::dvec3(irradianceAt(p, N)) * double(weight);
            cornerTotal = weight;
        }
        // What the probe cannot see, its extrapolated stand-in fills, as much as the axes it
        // comes from lie along N: renormalising over the probes that see the point alone
        // would read a face whose probes behind are hidden as its probes in front read it
        // (the Cornell box's blocks 5-10 % dark at the project's scale).
        glm::vec3 filled;
        const float along = v < 1.0f ? extrapolated(g, offset, N, biased, filled) : 0.0f;
        if (along > 0.0f) {
            const double share = double(1.0f - v) * std::min(double(along), 1.0);
            cornerSum += glm::dvec3(filled) * share;
            cornerTotal += share;
        }
        sum += cornerSum * trilinear[corner];
        total += cornerTotal * trilinear[corner];
    }
    return total > 0.0 ? glm::vec3(sum / total) : glm::vec3(0.0f);
}

glm::vec3 ProbeVolume::reflectedAt(const PbrSurface& s, const glm::vec3& P, const glm::vec3& N,
                                   const glm::vec3& V, bool specularLobe,
                                   const Visibility* scene) const {
    const float NdotV = std::max(glm::dot(N, V), 0.0f);
    glm::vec3 L = diffuseAlbedo(s, NdotV) / kPi * irradianceAt(P, N, V, scene);
    if (specularLobe) {
        const float a = s.alpha();
        const glm::vec3 D = glm::normalize(
            glm::mix(N, glm::reflect(-V, N), (1.0f - a) * (std::sqrt(1.0f - a) + a)));
        L += specularAlbedo(s, NdotV) / kPi * irradianceAt(P, D, V, scene);
    }
    return L;
}

} // namespace dhdr
