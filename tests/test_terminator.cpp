// The shadow terminator of smooth low-poly meshes (issue 46): shadow rays from a smooth-shaded
// triangle start from the point its vertex normals lift it to (Hanika 2021), so that a lone
// convex mesh shades as the smooth surface would; and the shading normal of a front face near
// a silhouette stays on the front (no single bright pixels).
#include "scene_builder.h"

#include <cmath>
#include <cstdio>
#include <dhdr/deferred/core/visibility.h>
#include <dhdr/deferred/direct/shadows.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/shading_point.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/geometry/surface.h>
#include <gtest/gtest.h>
#include <random>
#include <vector>

using namespace dhdr;
using namespace dhdr::test;

namespace {

[[maybe_unused]] auto* const kKernel = ::testing::AddGlobalTestEnvironment(new EmbreeKernel);

constexpr double kPi = 3.14159265358979323846;

// The side wall of an n-sided prism about the y axis (radius r, y in [−h, h]), each vertex's
// normal the circle's radial direction: a cylinder shaded smooth. Facet k spans the angles
// 2πk/n to 2π(k+1)/n, measured from +x towards −z.
Scene cylinder(int n, double r, double h) {
    Scene scene = emptyScene();
    Mesh m;
    for (int k = 0; k <= n; ++k) {
        const double a = 2.0 * kPi * k / n;
        const glm::vec3 radial(float(std::cos(a)), 0.0f, float(-std::sin(a)));
        for (double y : {-h, h}) {
            m.positions.push_back(float(r) * radial + glm::vec3(0.0f, float(y), 0.0f));
            m.normals.push_back(radial);
        }
    }
    for (int k = 0; k < n; ++k) {
        const unsigned a = unsigned(2 * k), b = unsigned(2 * k + 2);
        m.triangles.push_back({a, b, a + 1});
        m.triangles.push_back({b, b + 1, a + 1});
    }
    scene.meshes.push_back(m);
    return scene;
}

// The SurfacePoint the lighting pass reads from a G-buffer pixel there: what dhdr-gbuffer
// writes of the surface a ray from `eye` meets at `target`.
struct Seen {
    SurfaceSample sample;
    SurfacePoint point;
};

Seen seenFrom(const Scene& scene, const RayCaster& caster, const glm::dvec3& eye,
              const glm::dvec3& target) {
    const Ray ray{eye, glm::normalize(target - eye)};
    const RayHit hit = caster.intersect(ray);
    EXPECT_TRUE(hit.hit);
    Seen s{surfaceGeometryAt(scene, ray, hit), {}};
    s.point = {glm::vec3(s.sample.position), glm::vec3(s.sample.geometric),
               float(s.sample.positionError), glm::vec3(s.sample.lift), glm::vec3(s.sample.normal)};
    return s;
}

// On a facet of an n-gon of radius r whose vertices A, B have the radial normals nA, nB, the
// point P = (1 − t) A + t B lies below A's tangent plane by t r (1 − cos Δ) and below B's by
// (1 − t) r (1 − cos Δ), Δ = 2π/n, so Hanika's lift is t (1 − t) r (1 − cos Δ) (nA + nB).
TEST(Terminator, LiftOfACylinderFacetIsTheClosedForm) {
    const int n = 12;
    const double r = 1.5, delta = 2.0 * kPi / n;
    const Scene scene = cylinder(n, r, 2.0);
    const RayCaster caster(scene);
    for (int k : {0, 5}) {
        const double a0 = k * delta, a1 = (k + 1) * delta;
        const glm::dvec3 nA(std::cos(a0), 0.0, -std::sin(a0)), nB(std::cos(a1), 0.0, -std::sin(a1));
        for (double t : {0.0, 0.1, 0.25, 0.5, 0.8, 1.0}) {
            const glm::dvec3 out = glm::normalize(nA + nB);
            // Aimed a little inside the edges, so that the ray meets this facet.
            const double tt = std::clamp(t, 1e-3, 1.0 - 1e-3);
            const glm::dvec3 Pt = r * ((1.0 - tt) * nA + tt * nB) + glm::dvec3(0.0, 0.3, 0.0);
            const Seen s = seenFrom(scene, caster, Pt + 3.0 * out, Pt);
            const glm::dvec3 flat(s.sample.position.x, 0.0, s.sample.position.z);
            const double ts = glm::dot(flat - r * nA, nB - nA) / (r * glm::dot(nB - nA, nB - nA));
            const glm::dvec3 expected = ts * (1.0 - ts) * r * (1.0 - std::cos(delta)) * (nA + nB);
            EXPECT_NEAR(glm::length(s.sample.lift - expected), 0.0, 1e-6)
                << "facet " << k << ", t " << t << " (hit at " << ts << ")";
        }
    }
}

// A flat-shaded triangle (its three normals equal) is not lifted, its G-buffer carries no Plift
// and its rays start where pbrt-v4's OffsetRayOrigin puts them, bit for bit.
TEST(Terminator, AFlatTriangleIsUnchangedBitForBit) {
    const glm::dvec3 v[3] = {{0.1, 0.2, 0.3}, {1.7, 0.4, -0.2}, {0.3, 1.9, 0.8}};
    const glm::dvec3 face = glm::normalize(glm::cross(v[1] - v[0], v[2] - v[0]));
    const glm::dvec3 tilted = glm::normalize(face + glm::dvec3(0.3, -0.2, 0.1));
    for (const glm::dvec3& n : {face, tilted}) {
        const glm::dvec3 normals[3] = {n, n, n};
        const glm::dvec3 w(0.2, 0.5, 0.3);
        const glm::dvec3 P = w.x * v[0] + w.y * v[1] + w.z * v[2];
        EXPECT_EQ(terminatorLift(v, normals, w, P, face), glm::dvec3(0.0));
    }
    // pbrt-v4 §6.8.6 written out again: the origin before the lift existed.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 1000; ++i) {
        SurfacePoint p{{u(rng) * 50.0f, u(rng) * 50.0f, u(rng)},
                       glm::normalize(glm::vec3(u(rng), u(rng), u(rng))),
                       1e-5f * (1.0f + u(rng))};
        p.N = glm::normalize(p.Ng + 0.3f * glm::vec3(u(rng), u(rng), u(rng)));
        const glm::vec3 w = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
        const float d = p.error * (std::abs(p.Ng.x) + std::abs(p.Ng.y) + std::abs(p.Ng.z));
        glm::vec3 offset = d * p.Ng;
        if (glm::dot(w, p.Ng) < 0.0f) offset = -offset;
        glm::vec3 o = p.P + offset;
        for (int c = 0; c < 3; ++c)
            o[c] = offset[c] > 0.0f   ? std::nextafter(o[c], INFINITY)
                   : offset[c] < 0.0f ? std::nextafter(o[c], -INFINITY)
                                      : o[c];
        const glm::vec3 got = offsetRayOrigin(p, w);
        for (int c = 0; c < 3; ++c)
            ASSERT_EQ(std::memcmp(&got[c], &o[c], sizeof(float)), 0) << i;
    }
    // A box's G-buffer has no Plift channel.
    Scene scene = emptyScene();
    addBox(scene, {-1, -1, -1}, {1, 1, 1});
    const Camera camera = Camera::lookAt({3.0, 2.0, 4.0}, {0.0, 0.0, 0.0}, {0, 1, 0}, 0.7);
    const ImageBuf g = gbufferOf(scene, camera, 8, 8);
    EXPECT_LT(g.spec().channelindex(gbuffer::kLift[0]), 0);
}

// Whatever the vertex normals (even ones turned past the triangle's plane), the lifted origin
// lies on the triangle's front side, in double, beyond the rounding of P and of the lift.
TEST(Terminator, TheLiftedOriginNeverLiesBelowTheTriangle) {
    std::mt19937 rng(46);
    std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
    int lifted = 0;
    for (int i = 0; i < 20000; ++i) {
        const double scale = std::pow(10.0, 3.0 * u(rng));
        const glm::dvec3 centre = glm::dvec3(u(rng), u(rng), u(rng)) * scale * 10.0;
        glm::dvec3 v[3];
        for (glm::dvec3& p : v)
            p = glm::dvec3(glm::vec3(centre + glm::dvec3(u(rng), u(rng), u(rng)) * scale));
        const glm::dvec3 face = glm::normalize(glm::cross(v[1] - v[0], v[2] - v[0]));
        glm::dvec3 normals[3];
        for (glm::dvec3& n : normals)
            n = glm::normalize(face + 1.5 * glm::dvec3(u(rng), u(rng), u(rng)));
        double a = unit(rng), b = unit(rng);
        if (a + b > 1.0) {
            a = 1.0 - a;
            b = 1.0 - b;
        }
        const glm::dvec3 w(1.0 - a - b, a, b);
        const glm::dvec3 P = w.x * v[0] + w.y * v[1] + w.z * v[2];
        const glm::dvec3 lift = terminatorLift(v, normals, w, P, face);
        // Up to the rounding of the clamp's subtraction.
        ASSERT_GE(glm::dot(lift, face), -1e-15 * (scale + glm::length(centre)));
        glm::dvec3 N = w.x * normals[0] + w.y * normals[1] + w.z * normals[2];
        N = glm::normalize(N);
        const glm::dvec3 vertices[3] = {v[0], v[1], v[2]};
        const SurfacePoint p{glm::vec3(P), glm::vec3(face), float(positionError(P, vertices)),
                             glm::vec3(lift), glm::vec3(N)};
        const glm::vec3 dir = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
        lifted += terminatorLiftShare(p, dir) > 0.0f;
        const glm::dvec3 o(offsetRayOrigin(p, dir));
        if (terminatorLiftShare(p, dir) > 0.0f || glm::dot(dir, glm::vec3(face)) >= 0.0f) {
            ASSERT_GT(glm::dot(o - v[0], face), 0.0) << i;
        }
    }
    EXPECT_GT(lifted, 2000); // the lifted branch was exercised
}

// The analytic terminator of a smooth-shaded facet: the interpolated normal
// (1 − t) nA + t nB faces the sun for t < t* = nA·L / (nA·L − nB·L).
double smoothLitFraction(const glm::dvec3& nA, const glm::dvec3& nB, const glm::dvec3& L) {
    const double a = glm::dot(nA, L), b = glm::dot(nB, L);
    if (a <= 0.0 && b <= 0.0) return 0.0;
    if (a >= 0.0 && b >= 0.0) return 1.0;
    const double t = a / (a - b);
    return a > 0.0 ? t : 1.0 - t;
}

// A 12-sided cylinder under a sun perpendicular to its axis: the share of each facet that is
// lit, N·L × visibility > 0, sampled across it, against the smooth surface's share, where the
// interpolated normal faces the sun. Without the lift the facet the terminator crosses was
// wholly dark (its triangle faces away: shadow rays went into the mesh), a step of up to
// N·L = sin 15° ≈ 0.26 at its lit edge.
TEST(Terminator, ACylindersShadowFollowsTheSmoothCosine) {
    const int n = 12, samples = 200;
    const double r = 1.0, delta = 2.0 * kPi / n;
    const Scene scene = cylinder(n, r, 4.0);
    const RayCaster caster(scene);
    for (double degrees : {91.0, 95.0, 100.0, 104.0, 113.0}) {
        // The sun from the direction at `degrees` from facet 0's middle (+x rotated by Δ/2).
        const double az = delta / 2.0 + degrees * kPi / 180.0;
        const glm::dvec3 L(std::cos(az), 0.0, -std::sin(az));
        double worst = 0.0;
        for (int k = 0; k < n; ++k) {
            const double a0 = k * delta, a1 = (k + 1) * delta;
            const glm::dvec3 nA(std::cos(a0), 0.0, -std::sin(a0)),
                nB(std::cos(a1), 0.0, -std::sin(a1));
            const glm::dvec3 out = glm::normalize(nA + nB);
            int lit = 0, litFlat = 0;
            for (int i = 0; i < samples; ++i) {
                const double t = (i + 0.5) / samples;
                const glm::dvec3 Pt = r * ((1.0 - t) * nA + t * nB);
                const Seen s = seenFrom(scene, caster, Pt + 3.0 * out, Pt);
                const glm::vec3 wi(L);
                if (!(glm::dot(glm::dvec3(s.sample.normal), L) > 0.0)) continue;
                lit += caster.transmittance(offsetRayOrigin(s.point, wi), wi, INFINITY) > 0.0f;
                SurfacePoint flat = s.point;
                flat.lift = glm::vec3(0.0f);
                litFlat += caster.transmittance(offsetRayOrigin(flat, wi), wi, INFINITY) > 0.0f;
            }
            const double expected = smoothLitFraction(nA, nB, L);
            const double got = double(lit) / samples;
            // Without the lift: the facet whose triangle faces away is dark where it is lit.
            if (glm::dot(out, L) < 0.0) {
                EXPECT_EQ(litFlat, 0) << degrees << "°, facet " << k;
            }
            worst = std::max(worst, std::abs(got - expected));
            EXPECT_NEAR(got, expected, 0.01) << "sun at " << degrees << "°, facet " << k;
        }
        std::printf("sun at %g°: largest |lit share − smooth share| of a facet %.3f\n", degrees,
                    worst);
    }
}

// A sun with a disk seen from the facet the terminator crosses, where every ray towards it
// leaves below the triangle's plane. Such samples were left out, and with none left the point
// counted as unshadowed: lit with a wall between it and the sun. Traced from the lifted
// point, they find the wall; with the wall gone the point is lit as a hard sun lights it.
TEST(Terminator, ASunsDiskDoesNotLightATerminatorFacetBehindAWall) {
    const int n = 12;
    const double delta = 2.0 * kPi / n;
    Scene scene = cylinder(n, 1.0, 4.0);
    const RayCaster open(scene);
    // Towards the sun 95° from facet 0's middle, on B's side: the facet faces away by 5°, the
    // part near B faces the sun by its normals.
    const double az = delta / 2.0 + 95.0 * kPi / 180.0;
    const glm::dvec3 L(std::cos(az), 0.0, -std::sin(az));
    const glm::dvec3 nA(1.0, 0.0, 0.0), nB(std::cos(delta), 0.0, -std::sin(delta));
    const glm::dvec3 Pt = 0.2 * nA + 0.8 * nB;
    const Seen s = seenFrom(scene, open, Pt + 3.0 * glm::normalize(nA + nB), Pt);
    ASSERT_GT(glm::dot(glm::dvec3(s.sample.normal), L), 0.05);
    ASSERT_LT(glm::dot(s.sample.geometric, L), 0.0);
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::vec3(-L);
    sun.angle = float(0.53 * kPi / 180.0);
    Light hard = sun;
    hard.angle = 0.0f;
    const glm::vec3 N(s.sample.normal);
    EXPECT_EQ(lightVisibility(sun, s.point, N, 1, 16, open), 1.0f);
    EXPECT_EQ(lightVisibility(hard, s.point, N, 1, 16, open), 1.0f);
    // A wall 3 units towards the sun, across its path.
    const glm::dvec3 c = glm::dvec3(s.sample.position) + 3.0 * L;
    const glm::dvec3 u = glm::normalize(glm::cross(L, glm::dvec3(0, 1, 0))) * 2.0;
    const glm::dvec3 v(0.0, 2.0, 0.0);
    addQuad(scene, glm::vec3(c - u - v), glm::vec3(c + u - v), glm::vec3(c + u + v),
            glm::vec3(c - u + v));
    const RayCaster walled(scene);
    EXPECT_EQ(lightVisibility(sun, s.point, N, 1, 16, walled), 0.0f);
    EXPECT_EQ(lightVisibility(hard, s.point, N, 1, 16, walled), 0.0f);
}

// Near a silhouette the interpolated normal of a front face can face away from the viewer.
// It was turned round, onto the triangle's back, and a light behind the silhouette then lit
// the pixel (single bright pixels on every smooth low-poly silhouette). The normal stays on the
// triangle's front, bent to just in front of the viewer in the plane of it and the view.
TEST(Terminator, ASilhouettesNormalStaysOnTheFrontFacingTheViewer) {
    const int n = 12;
    const double delta = 2.0 * kPi / n;
    const Scene scene = cylinder(n, 1.0, 4.0);
    const RayCaster caster(scene);
    // Facet 0: from +x (A) to the angle Δ (B), its face normal at Δ/2. A ray nearly along the
    // facet towards B meets it where the interpolated normal, close to nB, faces away.
    const glm::dvec3 nA(1.0, 0.0, 0.0), nB(std::cos(delta), 0.0, -std::sin(delta));
    const glm::dvec3 face = glm::normalize(nA + nB), along = glm::normalize(nB - nA);
    const glm::dvec3 target = 0.95 * nB + 0.05 * nA;
    const glm::dvec3 dir = glm::normalize(along - 0.05 * face);
    const Seen s = seenFrom(scene, caster, target - 2.0 * dir, target);
    const glm::dvec3 interpolated = glm::normalize(0.05 * nA + 0.95 * nB);
    ASSERT_GT(glm::dot(interpolated, dir), 0.0) << "the set-up: the normal faces away";
    EXPECT_FALSE(s.sample.backFace);
    EXPECT_GT(glm::dot(s.sample.geometric, face), 0.99);
    EXPECT_GE(glm::dot(s.sample.normal, -dir), 1e-3 - 1e-12);
    EXPECT_LT(glm::dot(s.sample.normal, -dir), 2e-3);
    EXPECT_GT(glm::dot(s.sample.normal, interpolated), 0.9); // bent, not turned round
    // Light from behind the silhouette, towards −nB: the normal turned round faced it fully
    // (N·L ≈ 1, a white pixel at the rim of the dark side); the bent one faces away from it.
    const glm::dvec3 towardsLight = -nB;
    ASSERT_GT(glm::dot(-interpolated, towardsLight), 0.99);
    EXPECT_LT(glm::dot(s.sample.normal, towardsLight), 0.0);
}

} // namespace
