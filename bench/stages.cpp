// dhdr-bench-stages GBUFFER.exr LIGHTS.json [RUNS [THREADS]]: the library calls the Python module
// wraps, timed in C++ on one frame (bench/python_overhead.py runs the same calls from Python and
// compares). Each call makes a new destination, as the Python return form does. Prints one
// "name best_ms median_ms" line per stage.
#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/scene/lights.h>
#include <dhdr/io/strip_reader.h>
#include <dhdr/tonemap/bloom.h>
#include <dhdr/tonemap/edge_aa.h>
#include <dhdr/tonemap/tone_map.h>
#include <functional>
#include <string>
#include <vector>

using namespace dhdr;

namespace {

void time(const char* name, int runs, const std::function<bool()>& call) {
    std::vector<double> ms;
    for (int i = 0; i < runs; ++i) {
        const auto t = std::chrono::steady_clock::now();
        if (!call()) {
            std::fprintf(stderr, "%s failed\n", name);
            std::exit(1);
        }
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t)
                         .count());
    }
    std::sort(ms.begin(), ms.end());
    std::printf("%s %.3f %.3f\n", name, ms.front(), ms[ms.size() / 2]);
    std::fflush(stdout);
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: dhdr-bench-stages GBUFFER.exr LIGHTS.json [RUNS [THREADS]]\n");
        return 2;
    }
    const int runs = argc > 3 ? std::atoi(argv[3]) : 9;
    const int threads = argc > 4 ? std::atoi(argv[4]) : 0;
    std::string error;
    StripReader reader;
    OIIO::ImageBuf gbuf;
    if (!reader.open(argv[1], 0, 0, 1 << 20, 0, error) ||
        !reader.read(reader.spec().y, reader.spec().y + reader.spec().height, gbuf, error)) {
        std::fprintf(stderr, "%s: %s\n", argv[1], error.c_str());
        return 1;
    }
    std::vector<Light> lights;
    std::vector<std::string> warnings;
    if (!readLightsFile(argv[2], lights, error, warnings)) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 1;
    }
    const LightingInputs inputs{lights, nullptr};
    OIIO::ImageBuf hdr;
    time("light", runs, [&] {
        hdr = OIIO::ImageBuf();
        return shadeGBuffer(hdr, gbuf, inputs, {}, {}, threads);
    });
    time("tone_map", runs, [&] {
        OIIO::ImageBuf dst;
        return toneMap(dst, hdr, {}, {}, threads);
    });
    time("bloom", runs, [&] {
        OIIO::ImageBuf dst;
        return bloom(dst, hdr, {}, {}, threads);
    });
    // Normal and depth as their own images, as the module gives edge_aa G-buffer channels.
    OIIO::ImageBuf normal, depth;
    const int n = gbuf.spec().channelindex("N.X"), z = gbuf.spec().channelindex("Z");
    const int order[3] = {n, n + 1, n + 2};
    OIIO::ImageBufAlgo::channels(normal, gbuf, 3, order);
    OIIO::ImageBufAlgo::channels(depth, gbuf, 1, &z);
    time("edge_aa", runs, [&] {
        OIIO::ImageBuf dst;
        return edgeAA(dst, hdr, &normal, &depth, {}, {}, threads);
    });
    return 0;
}
