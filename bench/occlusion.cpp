// Occlusion rays per second per thread: one rtcOccluded1 call per ray against batches through
// rtcOccluded1M (RayCaster::transmittance and RayCaster::test), for incoherent rays like
// soft-shadow and AO rays; then hard-shadow rays from a 1920x1080 frame's first hits towards
// one point light, tile by tile (16x16), one at a time, in batches and in coherent packets of
// 16 (RayCaster::testCoherent); then a sun's soft-shadow rays, 16, 8 or 4 per pixel from one
// point over a 0.5° disk, pixel by pixel as the shading traces them, in batches and in packets.
// Usage: dhdr-bench-occlusion SCENE [RAYS]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/geometry/ray_caster.h>
#include <dhdr/deferred/geometry/surface.h>
#include <dhdr/deferred/scene/scene.h>
#include <string>
#include <vector>

using namespace dhdr;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: dhdr-bench-occlusion SCENE [RAYS]\n");
        return 2;
    }
    const size_t count = argc > 2 ? size_t(std::atoll(argv[2])) : 4000000;
    Scene scene;
    std::string error;
    if (!loadScene(argv[1], scene, error)) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 1;
    }
    const RayCaster caster(scene);
    // Origins uniform in the scene's bounds, directions uniform on the sphere, length up to
    // the bounds' diagonal: no two consecutive rays alike.
    const glm::vec3 lo(scene.boundsMin()), hi(scene.boundsMax());
    const float diagonal = glm::length(hi - lo);
    std::vector<ShadowRay> rays(count);
    for (size_t i = 0; i < count; ++i) {
        const std::uint64_t s = sampleSeed(std::int64_t(i), 0);
        auto u = [&](int k) { return unitFloat(mixBits(s + std::uint64_t(k))); };
        const glm::vec3 origin = lo + (hi - lo) * glm::vec3(u(1), u(2), u(3));
        const float z = 1.0f - 2.0f * u(4), phi = 2.0f * kPi * u(5);
        const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        rays[i] = {origin, {r * std::cos(phi), r * std::sin(phi), z}, diagonal * u(6)};
    }
    std::vector<float> one(count);
    auto t0 = std::chrono::steady_clock::now();
    for (size_t i = 0; i < count; ++i)
        one[i] = caster.transmittance(rays[i].origin, rays[i].direction, rays[i].tmax);
    auto t1 = std::chrono::steady_clock::now();
    std::vector<float> batch(count);
    caster.test(rays.data(), count, batch.data());
    auto t2 = std::chrono::steady_clock::now();
    size_t disagree = 0, visible = 0;
    for (size_t i = 0; i < count; ++i) {
        disagree += one[i] != batch[i];
        visible += batch[i] == 1.0f;
    }
    const double s1 = std::chrono::duration<double>(t1 - t0).count();
    const double sm = std::chrono::duration<double>(t2 - t1).count();
    std::printf("%zu incoherent rays on one thread, %.1f %% unoccluded\n", count,
                100.0 * double(visible) / double(count));
    std::printf("rtcOccluded1:  %.2f M rays/s\n", double(count) / s1 / 1e6);
    std::printf("rtcOccluded1M: %.2f M rays/s (batches of 64)\n", double(count) / sm / 1e6);
    std::printf("answers that differ: %zu\n", disagree);

    // Hard shadows: the scene's first camera (or one looking at its bounds from +z), each
    // pixel's first hit, a ray to a light near the top of the bounds; tile by tile.
    const int W = 1920, H = 1080, T = 16;
    Camera camera =
        scene.cameras.empty()
            ? Camera::lookAt(glm::dvec3((lo + hi) * 0.5f) + glm::dvec3(0.0, 0.0, 1.5 * diagonal),
                             glm::dvec3((lo + hi) * 0.5f), {0, 1, 0}, 0.7)
            : scene.cameras[0].camera;
    const glm::vec3 light = lo + (hi - lo) * glm::vec3(0.5f, 0.9f, 0.5f);
    std::vector<ShadowRay> hard;
    for (int ty = 0; ty < H; ty += T)
        for (int tx = 0; tx < W; tx += T)
            for (int y = ty; y < std::min(H, ty + T); ++y)
                for (int x = tx; x < std::min(W, tx + T); ++x) {
                    const Ray ray = camera.primaryRay(x, y, W, H);
                    const RayHit hit = caster.intersect(ray);
                    if (!hit.hit || hit.mesh < 0) continue;
                    const SurfaceSample s = surfaceAt(scene, ray, hit);
                    const SurfacePoint at{glm::vec3(s.position), glm::vec3(s.geometric),
                                          float(s.positionError)};
                    const glm::vec3 to = light - at.P;
                    const float distance = glm::length(to);
                    const glm::vec3 d = to / distance;
                    if (!(glm::dot(d, at.Ng) > 0.0f)) continue;
                    hard.push_back({offsetRayOrigin(at, d), d, distance * 0.999f});
                }
    const size_t nh = hard.size();
    std::vector<float> single(nh), batched(nh), packets(nh);
    auto h0 = std::chrono::steady_clock::now();
    for (size_t i = 0; i < nh; ++i)
        single[i] = caster.transmittance(hard[i].origin, hard[i].direction, hard[i].tmax);
    auto h1 = std::chrono::steady_clock::now();
    caster.test(hard.data(), nh, batched.data());
    auto h2 = std::chrono::steady_clock::now();
    caster.testCoherent(hard.data(), nh, packets.data());
    auto h3 = std::chrono::steady_clock::now();
    size_t differ = 0, lit = 0;
    for (size_t i = 0; i < nh; ++i) {
        differ += single[i] != batched[i] || single[i] != packets[i];
        lit += single[i] == 1.0f;
    }
    auto rate = [&](auto a, auto b) {
        return double(nh) / std::chrono::duration<double>(b - a).count() / 1e6;
    };
    std::printf("%zu hard-shadow rays of a %dx%d frame to one point light, tile by tile, "
                "%.1f %% unoccluded\n",
                nh, W, H, 100.0 * double(lit) / double(nh));
    std::printf("rtcOccluded1:  %.2f M rays/s\n", rate(h0, h1));
    std::printf("rtcOccluded1M: %.2f M rays/s (incoherent batches of 64)\n", rate(h1, h2));
    std::printf("rtcOccluded16: %.2f M rays/s (coherent packets)\n", rate(h2, h3));
    std::printf("answers that differ: %zu\n", differ);

    // A sun: 16 directions within 0.25° of one, from each first hit that faces it.
    const glm::vec3 sun = glm::normalize(glm::vec3(0.3f, 0.9f, 0.2f));
    glm::vec3 t, b;
    orthonormalBasis(sun, t, b);
    const float spread = std::tan(0.25f * kPi / 180.0f);
    std::vector<ShadowRay> disk;
    for (const ShadowRay& r : hard)
        for (int k = 0; k < 16; ++k) {
            const float a = 2.0f * kPi * (float(k) + 0.5f) / 16.0f,
                        rr = std::sqrt((k % 4 + 0.5f) / 4.0f);
            const glm::vec3 d =
                glm::normalize(sun + spread * rr * (std::cos(a) * t + std::sin(a) * b));
            disk.push_back({r.origin, d, INFINITY});
        }
    const size_t nd = disk.size();
    std::vector<float> diskBatched(nd), diskPackets(nd);
    size_t diskDiffer = 0;
    // Per pixel 16 rays (a sun's soft shadow), 8, or 4 (the sun's first rays, shadows.cpp's
    // sunDiskProbe): testCoherent traces them in one packet of 16, 8 or 4.
    for (const size_t each : {size_t(16), size_t(8), size_t(4)}) {
        auto d0 = std::chrono::steady_clock::now();
        for (size_t i = 0; i < nd; i += 16)
            caster.test(disk.data() + i, each, diskBatched.data() + i);
        auto d1 = std::chrono::steady_clock::now();
        for (size_t i = 0; i < nd; i += 16)
            caster.testCoherent(disk.data() + i, each, diskPackets.data() + i);
        auto d2 = std::chrono::steady_clock::now();
        for (size_t i = 0; i < nd; i += 16)
            for (size_t k = 0; k < each; ++k)
                diskDiffer += diskBatched[i + k] != diskPackets[i + k];
        auto diskRate = [&](auto a, auto b) {
            return double(nd / 16 * each) / std::chrono::duration<double>(b - a).count() / 1e6;
        };
        std::printf("%zu sun-disk rays, %zu per pixel from one point\n", nd / 16 * each, each);
        std::printf("rtcOccluded1M: %.2f M rays/s (%zu a call)\n", diskRate(d0, d1), each);
        std::printf("rtcOccluded%zu: %.2f M rays/s (one coherent packet a pixel)\n", each,
                    diskRate(d1, d2));
    }
    std::printf("answers that differ: %zu\n", diskDiffer);
    return disagree || differ || diskDiffer ? 1 : 0;
}
