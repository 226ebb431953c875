// Occlusion rays per second per thread on the Cornell box: one rtcOccluded1 call per ray
// against batches through rtcOccluded1M (RayCaster::occluded and RayCaster::test), for
// incoherent rays like soft-shadow and AO rays. Usage: dhdr-bench-occlusion SCENE [RAYS]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <dhdr/deferred/ray_caster.h>
#include <dhdr/deferred/sampling.h>
#include <dhdr/deferred/scene.h>
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
    return disagree ? 1 : 0;
}
