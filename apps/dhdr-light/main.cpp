// dhdr-light: a G-buffer and a lights file in, linear HDR radiance out (docs/tools.md).
#include "../common/frames.h"
#include "../common/strip_reader.h"
#include "../common/tool.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <dhdr/deferred/gbuffer.h>
#include <dhdr/deferred/lighting.h>
#include <dhdr/tonemap/sanitize.h>
#include <filesystem>
#include <future>

using namespace dhdr;

namespace {

int run(int argc, char** argv) {
    app::CommandLine cl(
        "dhdr-light", "GBUFFER.exr --lights LIGHTS.json... -o FRAME.exr [options]",
        "Deferred lighting: shades every covered pixel of a G-buffer with Lambert diffuse plus\n"
        "Cook-Torrance specular (GGX, height-correlated Smith, Schlick) under point, spot,\n"
        "directional, ambient, sphere and rectangle lights (docs/lights.md), adds emission,\n"
        "and writes linear HDR RGBA. Each light is evaluated only in the tiles its screen\n"
        "rectangle covers. Half output clamps radiance past 65504 (and says how many values);\n"
        "--type float keeps it.");
    std::vector<std::string> lightsPaths;
    std::string background, dataType = "half";
    bool bruteForce = false, aovs = false;
    int tileSize = 16;
    cl.option("--lights", "FILE",
              "lights file (JSON, docs/lights.md); required; repeat to add the lights of several",
              [&](const std::string& v, std::string&) {
                  lightsPaths.push_back(v);
                  return true;
              });
    cl.option("--background", background, "R,G,B[,A]",
              "colour where there is no surface (default: transparent black)");
    cl.flag("--brute-force", bruteForce, "evaluate every light at every pixel (the reference)");
    cl.option("--tile", tileSize, "N", "tile size of the light lists in pixels (default 16)", 1,
              1024);
    cl.flag("--aovs", aovs, "also write the G-buffer's Z and N.X N.Y N.Z channels");
    cl.option("--type", dataType, "half|float", "pixel type of the output EXR (default half)");
    cl.epilog("Example:\n  dhdr-light frame.gbuf.exr --lights testdata/cornell_box.lights.json "
              "-o frame.hdr.exr");
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-light", cl);
    if (cl.inputs().size() != 1) {
        std::fprintf(stderr, "dhdr-light: usage error: give one G-buffer file\n");
        return app::kExitUsage;
    }
    if (lightsPaths.empty()) {
        std::fprintf(stderr, "dhdr-light: usage error: no lights file (--lights FILE)\n");
        return app::kExitUsage;
    }
    if (dataType != "half" && dataType != "float") {
        std::fprintf(stderr, "dhdr-light: usage error: --type must be half or float\n");
        return app::kExitUsage;
    }
    LightingParams params;
    params.bruteForce = bruteForce;
    params.tileSize = tileSize;
    if (!background.empty()) {
        std::vector<double> v;
        if (!app::parseNumbers(background, v) || (v.size() != 3 && v.size() != 4)) {
            std::fprintf(stderr, "dhdr-light: usage error: --background needs 3 or 4 numbers\n");
            return app::kExitUsage;
        }
        for (size_t i = 0; i < 4; ++i)
            params.background[i] = i < v.size() ? float(v[i]) : 1.0f;
    }
    if (aovs) params.passThrough = {"Z", "N.X", "N.Y", "N.Z"};
    std::vector<std::string> paths = {cl.inputs()[0]};
    paths.insert(paths.end(), lightsPaths.begin(), lightsPaths.end());
    app::FramePlan plan;
    if (const int status = app::planFrames(tool, paths, plan); status >= 0) return status;

    auto readLights = [&](const std::vector<std::string>& files, std::vector<Light>& lights) {
        lights.clear();
        for (const std::string& file : files) {
            std::vector<Light> more;
            std::string error;
            if (!readLightsFile(file, more, error)) {
                tool.fail(error);
                return false;
            }
            lights.insert(lights.end(), more.begin(), more.end());
        }
        return true;
    };
    // Lights files without a frame pattern hold the same lights for every frame: read once.
    const bool animatedLights =
        std::any_of(plan.inputs.begin() + 1, plan.inputs.end(),
                    [](const app::FramePattern& p) { return p.isSequence(); });
    std::vector<Light> lights;
    if (!animatedLights && !readLights(lightsPaths, lights)) return app::kExitFailure;

    return app::runFrames(tool, plan, [&](int, const auto& in, const auto& out) {
        const std::string& path = in[0];
        if (animatedLights && !readLights({in.begin() + 1, in.end()}, lights)) return false;
        const auto start = std::chrono::steady_clock::now();
        if (!std::filesystem::exists(path)) {
            tool.fail(path + ": no such file");
            return false;
        }
        std::string error;
        const int part = gbuffer::findGBufferPart(path, error);
        if (part < 0) {
            tool.fail(
                path + ": " +
                (error.find("G-buffer") != std::string::npos ? error : "cannot read: " + error));
            return false;
        }
        app::StripReader reader;
        if (!reader.open(path, part, 0, 1 << 20, tool.threads(), error)) {
            tool.fail(path + ": cannot read: " + error);
            return false;
        }
        const OIIO::ImageSpec& gspec = reader.spec();
        gbuffer::Layout layout;
        std::string missing;
        if (!gbuffer::findLayout(gspec, layout, missing)) {
            tool.fail(path + ": no channel '" + missing + "' — is this a G-buffer?");
            return false;
        }
        if (gbuffer::CameraInfo camera; !gbuffer::readCamera(gspec, camera, error)) {
            tool.fail(path + ": " + error);
            return false;
        }
        // Strip by strip, whole rows of tiles at a time: memory stays at one strip of the
        // G-buffer and one of the output whatever the frame's size, and each pixel's result
        // is the same as from the whole frame (tiles are laid over the frame).
        LightingParams strips = params;
        strips.frame = OIIO::get_roi(gspec);
        const int rows = tileSize * std::max(1, 128 / tileSize);
        std::string lightFiles;
        for (size_t i = 1; i < in.size(); ++i)
            lightFiles += (i > 1 ? ", " : "") + in[i];
        app::AtomicOutput file(tool, out);
        OIIO::ImageBuf hdr;
        LightingStats stats;
        NonFiniteCount replaced;
        double readMs = 0.0, shadeMs = 0.0, writeMs = 0.0;
        auto since = [](auto t) {
            return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t)
                .count();
        };
        app::Progress progress(tool, "dhdr-light: " + path);
        // The next strip is read on another thread while this one is shaded and written:
        // decoding the G-buffer is most of the work.
        OIIO::ImageBuf buffers[2];
        auto readAhead = [&](int y, int k) {
            return std::async(std::launch::async, [&, y, k] {
                std::string e;
                return reader.read(y, y + rows, buffers[k], e) ? std::string() : "x" + e;
            });
        };
        std::future<std::string> next = readAhead(gspec.y, 0);
        int k = 0;
        for (int y = gspec.y; y < gspec.y + gspec.height; y += rows, k ^= 1) {
            auto t = std::chrono::steady_clock::now();
            if (const std::string e = next.get(); !e.empty()) {
                tool.fail(path + ": cannot read: " + e.substr(1));
                return false;
            }
            if (y + rows < gspec.y + gspec.height) next = readAhead(y + rows, k ^ 1);
            OIIO::ImageBuf& gbuf = buffers[k];
            // Z is +∞ on the background by contract; every other channel must be finite.
            for (const auto& [c0, c1] :
                 {std::pair(0, layout.depth), std::pair(layout.depth + 1, gbuf.nchannels())}) {
                OIIO::ROI channels = gbuf.roi();
                channels.chbegin = c0;
                channels.chend = c1;
                if (c1 > c0) replaced += replaceNonFinite(gbuf, channels, tool.threads());
            }
            readMs += since(t);
            t = std::chrono::steady_clock::now();
            LightingStats strip;
            if (!shadeGBuffer(hdr, gbuf, {lights}, strips, {}, tool.threads(), &strip)) {
                tool.fail(path + ": " + hdr.geterror());
                return false;
            }
            stats.lightEvaluations += strip.lightEvaluations;
            stats.lightsReaching += strip.lightsReaching;
            stats.coveredPixels += strip.coveredPixels;
            stats.tileListEntries += strip.tileListEntries;
            shadeMs += since(t);
            t = std::chrono::steady_clock::now();
            if (y == gspec.y) {
                OIIO::ImageSpec spec = hdr.spec();
                spec.y = gspec.y;
                spec.height = gspec.height;
                spec.attribute("dhdr:lights", lightFiles);
                spec.erase_attribute("dhdr:materialNames");
                spec.erase_attribute("dhdr:objectNames");
                if (!file.open(spec,
                               {dataType == "half" ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT}))
                    return false;
            }
            if (!file.writeRows(hdr.spec().y, hdr.spec().y + hdr.spec().height,
                                static_cast<const float*>(hdr.localpixels())))
                return false;
            writeMs += since(t);
            progress.update(float(y + rows - gspec.y) / float(gspec.height));
        }
        if (!file.commit()) return false;
        tool.reportNonFinite(path, replaced, false);
        if (stats.coveredPixels == 0)
            tool.warn(path + ": no surface in view: A is 0 everywhere (an empty frame)");

        auto ms = [](double v) { return std::to_string(int(v + 0.5)) + " ms"; };
        const double pixels = double(std::max<long long>(stats.coveredPixels, 1));
        char line[200];
        std::snprintf(line, sizeof line,
                      "%zu lights; per covered pixel %.2f considered, %.2f within range%s; "
                      "%lld tile-list entries",
                      lights.size(), double(stats.lightEvaluations) / pixels,
                      double(stats.lightsReaching) / pixels, bruteForce ? " (brute force)" : "",
                      stats.tileListEntries);
        tool.info(line);
        tool.info("total " + ms(since(start)) + ": read " + ms(readMs) + ", shade " + ms(shadeMs) +
                  ", write " + ms(writeMs) +
                  (reader.streamed() ? "" : " (read whole: not a scanline EXR)"));
        return true;
    });
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-light", [&] { return run(argc, argv); });
}
