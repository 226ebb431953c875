// What each libFuzzer target of fuzz/ does with one input, shared with the regression test
// that replays the seeds and the inputs of past crashes (tests/test_fuzz_regressions.cpp):
// a crash found by fuzzing is reproduced through exactly the calls that found it.
#pragma once

#include "load/gltf_json.h"

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer_import.h>
#include <dhdr/deferred/gbuffer/shading_point.h>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/deferred/scene/lights.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/io/deep_exr.h>
#include <dhdr/io/exr_header.h>
#include <filesystem>
#include <map>
#include <string>
#include <unistd.h>
#include <vector>

namespace dhdr::fuzz {

// One directory per process (/dev/shm when there is one, else the temporary directory),
// holding the input as `name`; removed, with anything a reader left in it, on destruction.
// Relative references inside the input (a glTF buffer's uri) resolve in that empty directory.
class TempInput {
public:
    TempInput(const uint8_t* data, size_t size, const std::string& name) {
        std::error_code ec;
        const std::filesystem::path base = std::filesystem::is_directory("/dev/shm", ec)
                                               ? std::filesystem::path("/dev/shm")
                                               : std::filesystem::temp_directory_path(ec);
        m_dir = base / ("dhdr-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(m_dir, ec);
        m_path = (m_dir / name).string();
        if (FILE* f = std::fopen(m_path.c_str(), "wb")) {
            if (size > 0) std::fwrite(data, 1, size, f);
            std::fclose(f);
        }
    }
    ~TempInput() {
        // OpenImageIO's shared ImageCache (behind an ImageBuf read by name) keeps the header
        // of each path it opened: forgotten, so that each input is read as itself and a
        // crash reproduces from its input alone.
        OIIO::ImageCache::create(true)->invalidate(OIIO::ustring(m_path), true);
        std::error_code ec;
        std::filesystem::remove_all(m_dir, ec);
    }
    TempInput(const TempInput&) = delete;
    TempInput& operator=(const TempInput&) = delete;

    const std::string& path() const { return m_path; }

private:
    std::filesystem::path m_dir;
    std::string m_path;
};

// OpenImageIO on one thread and OpenEXR without its thread pool (exr_threads −1): the fuzzers
// run beside other work, a single thread keeps a crash reproducible, and a pool set up again
// for each file halved the executions a second.
inline void initImageLibraries() {
    OIIO::attribute("threads", 1);
    OIIO::attribute("exr_threads", -1);
}

// Images larger than this (pixels × channels) are skipped by the image targets: the tools
// stream large frames in strips, and a header claiming gigapixels would only make libFuzzer
// report running out of memory in OpenImageIO's allocation of the whole frame.
inline constexpr long long kMaxValues = 1LL << 22;

inline bool smallEnough(const OIIO::ImageSpec& spec) {
    if (spec.width <= 0 || spec.height <= 0 || spec.depth <= 0 || spec.nchannels <= 0) return false;
    const long long values =
        (long long)spec.width * spec.height * spec.depth * (long long)spec.nchannels;
    return values > 0 && values <= kMaxValues && spec.width <= (1 << 16) &&
           spec.height <= (1 << 16);
}

// Keeps the optimizer from dropping reads whose results are otherwise unused.
inline volatile float g_kept = 0.0f;
inline void keep(float value) {
    g_kept = value;
}

inline bool isGlb(const uint8_t* data, size_t size) {
    return size >= 4 && std::memcmp(data, "glTF", 4) == 0;
}

// fuzz_lights: the lights-file parser.
inline void lights(const uint8_t* data, size_t size) {
    const std::string json(reinterpret_cast<const char*>(data), size);
    std::vector<Light> lights;
    std::string error;
    parseLights(json, lights, error);
}

// fuzz_gltf_json: what dhdr reads of a glTF file's JSON itself (libdeferred/src/load/gltf_json.h),
// the input as a .gltf (a .glb when it starts with the binary magic): the document as
// loadScene reads it, then every reader of it, as loadScene calls them.
inline void gltfJson(const uint8_t* data, size_t size) {
    TempInput input(data, size, isGlb(data, size) ? "input.glb" : "input.gltf");
    const std::string& path = input.path();
    const nlohmann::json doc = detail::gltfJson(path);
    std::string bytes, error;
    detail::gltfFlattenDeepNodes(path, doc, bytes, error);
    detail::gltfEmissiveStrengths(doc);
    detail::gltfMaterialTextures(doc);
    detail::gltfIgnoredFeatures(doc);
    detail::gltfEmptySceneReason(doc);
    detail::gltfCamerasByNode(doc);
    detail::gltfNames(doc, "nodes");
    detail::gltfNames(doc, "meshes");
    std::map<std::string, detail::GltfLight> lights;
    detail::gltfLightsByNode(doc, lights, error);
}

// fuzz_scene: loadScene (Assimp's importer, then dhdr's scene loader) on the same file.
inline void scene(const uint8_t* data, size_t size) {
    TempInput input(data, size, isGlb(data, size) ? "input.glb" : "input.gltf");
    Scene scene;
    std::string error;
    loadScene(input.path(), scene, error);
}

// fuzz_channel_map: the channel-map reader.
inline void channelMap(const uint8_t* data, size_t size) {
    TempInput input(data, size, "input.json");
    ChannelMap map;
    std::string error;
    readChannelMap(input.path(), map, error);
}

inline void readFlatGBuffer(const std::string& path, int part) {
    OIIO::ImageBuf buf(path, part, 0);
    if (!buf.read(part, 0, true, OIIO::TypeDesc::FLOAT)) return;
    GBufferPixels g;
    OIIO::ImageBuf errors;
    if (!openGBuffer(buf, g, errors)) return;
    const OIIO::ImageSpec& spec = g.pixels->spec();
    GBufferView view(*g.pixels, g.layout, g.camera);
    float sum = 0.0f;
    for (int y = spec.y; y < spec.y + spec.height; ++y)
        for (int x = spec.x; x < spec.x + spec.width; ++x)
            if (view.samples(x, y) > 0) sum += view.at(x, y).coverage;
    keep(sum);
}

inline void readDeepGBufferPart(const std::string& path, int part, const OIIO::ImageSpec& spec) {
    std::string error;
    DeepGBuffer g;
    long long replaced = 0;
    if (readDeepGBuffer(path, part, g, error, &replaced)) {
        gbuffer::Layout layout;
        gbuffer::CameraInfo camera;
        std::string missing;
        if (gbuffer::findLayout(g.spec, layout, missing) &&
            gbuffer::readCamera(g.spec, camera, error)) {
            GBufferView view(g, layout, camera);
            float sum = 0.0f;
            for (int y = g.spec.y; y < g.spec.y + g.spec.height; ++y)
                for (int x = g.spec.x; x < g.spec.x + g.spec.width; ++x)
                    for (int k = 0, n = view.samples(x, y); k < n; ++k)
                        sum += view.at(x, y, k).depth;
            keep(sum);
        }
    }
    if (spec.tile_width == 0) {
        DeepScanlineReader reader;
        OIIO::DeepData samples;
        if (reader.open(path, part, spec, error))
            reader.read(spec.y, spec.y + spec.height, samples, error);
    }
}

// fuzz_gbuffer: the input as an .exr; findGBufferPart picks the part; a flat part is read as
// the lighting pass reads it (an ImageBuf as float, openGBuffer, every pixel's shading point
// through GBufferView), a deep one through readDeepGBuffer (its samples through GBufferView)
// and through DeepScanlineReader, OpenEXR's own deep reads.
inline void gbufferFile(const uint8_t* data, size_t size) {
    TempInput input(data, size, "input.exr");
    const std::string& path = input.path();
    std::string error;
    const int part = gbuffer::findGBufferPart(path, error);
    if (part < 0) return;
    OIIO::ImageSpec spec;
    {
        auto in = OIIO::ImageInput::open(path);
        if (!in || !in->seek_subimage(part, 0)) return;
        spec = in->spec();
    }
    if (!smallEnough(spec)) return;
    if (spec.deep)
        readDeepGBufferPart(path, part, spec);
    else
        readFlatGBuffer(path, part);
}

// fuzz_probes: the probe-file reader, and the lookups the lighting pass makes in what it read.
inline void probes(const uint8_t* data, size_t size) {
    TempInput input(data, size, "input.exr");
    ProbeVolume volume;
    std::string error;
    if (!readProbes(input.path(), volume, error)) return;
    const glm::vec3 dirs[] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0.577f, -0.577f, 0.577f}};
    float sum = 0.0f;
    const int n = std::min(volume.probeCount(), 64);
    for (int p = 0; p < n; ++p)
        for (const glm::vec3& d : dirs)
            sum += volume.irradianceAt(p, d).x + volume.distanceAt(p, d).x;
    keep(sum);
}

// fuzz_ibl: loadIbl, a baked file as it is or an environment baked here with tiny parameters
// so that one input stays fast, then one shading lookup.
inline void ibl(const uint8_t* data, size_t size) {
    TempInput input(data, size, "input.exr");
    // The size is looked at before loadIbl bakes: through the same look at the headers that
    // loadIbl makes before it opens the file.
    std::string error;
    if (!detail::exrHeadersFit(input.path(), error)) return;
    {
        auto in = OIIO::ImageInput::open(input.path());
        if (!in || !smallEnough(in->spec())) return;
    }
    IblBakeParams params;
    params.levels = 2;
    params.baseWidth = 8;
    params.samples = 1;
    params.dfgSize = 4;
    params.dfgSamples = 4;
    Ibl ibl;
    bool baked = false;
    long long replaced = 0;
    if (!loadIbl(input.path(), params, ibl, baked, error, &replaced, 1)) return;
    const IblShading shaded =
        shadeIbl(ibl, PbrSurface{}, glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(0.0f, 0.6f, 0.8f));
    keep(shaded.diffuse.x + shaded.specular.y);
}

// Every target by name (the fuzz/ executables are fuzz_<name>).
struct Target {
    const char* name;
    void (*run)(const uint8_t*, size_t);
};
inline constexpr Target kTargets[] = {
    {"fuzz_lights", lights},
    {"fuzz_gltf_json", gltfJson},
    {"fuzz_scene", scene},
    {"fuzz_channel_map", channelMap},
    {"fuzz_gbuffer", gbufferFile},
    {"fuzz_probes", probes},
    {"fuzz_ibl", ibl},
};

} // namespace dhdr::fuzz
