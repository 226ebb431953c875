// dhdr-ibl: bakes an equirectangular HDR environment for image-based lighting (docs/ibl.md).
#include "../common/param_options.h"
#include "../common/tool.h"

#include <chrono>
#include <cstdio>
#include <dhdr/deferred/environment/ibl.h>

using namespace dhdr;

namespace {

int run(int argc, char** argv) {
    app::CommandLine cl(
        "dhdr-ibl", "ENV.exr -o ENV.ibl.exr [options]",
        "Bakes an equirectangular HDR environment (2:1, any format OpenImageIO reads) for\n"
        "dhdr-light's environment lights, as Filament's cmgen does: diffuse irradiance as 9\n"
        "spherical harmonics, a chain of GGX-prefiltered levels (one roughness per level,\n"
        "a quadrature over the source mips, finer towards the lobe's centre, with the\n"
        "brightest texels added exactly), and the\n"
        "split-sum DFG table with the multiple-scattering terms. One multi-part EXR: the\n"
        "levels as subimages, then the DFG table; the SH and parameters in the header.");
    IblBakeParams p;
    app::addParamOptions(cl, p, kIblBakeParamTable);
    app::addParamOptions(cl, p, kIblBakeFloatTable);
    cl.epilog("Example:\n  dhdr-ibl studio.exr -o studio.ibl.exr\n"
              "  then in a lights file: {\"type\": \"environment\", \"image\": "
              "\"studio.ibl.exr\"}");
    if (const int status = cl.parse(argc, argv); status >= 0) return status;
    app::Tool tool("dhdr-ibl", cl);
    if (cl.inputs().size() != 1 || cl.output().empty()) {
        std::fprintf(stderr, "dhdr-ibl: usage error: give one environment and -o OUTPUT\n");
        return app::kExitUsage;
    }
    // The output checks every tool makes: not the environment, in a folder that exists.
    if (const int status = tool.start(cl.inputs()); status >= 0) return status;
    const std::string& path = cl.inputs()[0];
    const auto t0 = std::chrono::steady_clock::now();
    EnvironmentImage env;
    std::string error;
    long long replaced = 0;
    if (!readEnvironmentImage(path, env, error, &replaced)) return tool.fail(path + ": " + error);
    if (replaced > 0)
        tool.warn(path + ": " + std::to_string(replaced) +
                  " NaN or infinite texel values replaced by 0");
    const auto t1 = std::chrono::steady_clock::now();
    Ibl ibl;
    if (!bakeIbl(env, p, ibl, error, tool.threads())) return tool.fail(path + ": " + error);
    const auto t2 = std::chrono::steady_clock::now();
    if (!tool.writeAtomically(cl.output(), [&](const std::string& temporary, std::string& why) {
            return writeIbl(temporary, ibl, why);
        }))
        return app::kExitFailure;
    const auto t3 = std::chrono::steady_clock::now();
    auto ms = [](auto a, auto b) {
        return std::to_string(int(std::chrono::duration<double, std::milli>(b - a).count())) +
               " ms";
    };
    char line[200];
    std::snprintf(line, sizeof line,
                  "%dx%d environment; %d levels from %d wide, quadrature of %d samples at level 1; "
                  "DFG %d² at "
                  "%d samples",
                  env.width, env.height, p.levels, p.baseWidth, p.samples, p.dfgSize, p.dfgSamples);
    tool.info(line);
    if (ibl.sun.found()) {
        const glm::vec3 d = ibl.sun.direction, e = ibl.sun.illuminance;
        std::snprintf(line, sizeof line,
                      "sun: towards (%.4f, %.4f, %.4f), %.3g° across, illuminance %.6g %.6g "
                      "%.6g, %.1f%% of the environment's light",
                      d.x, d.y, d.z, double(ibl.sun.angle) * 57.29577951308232, e.r, e.g, e.b,
                      100.0 * ibl.sun.share);
        tool.info(line);
    } else {
        tool.info(p.sunThreshold > 0.0f ? "sun: none above the threshold (or wider than 20°)"
                                        : "sun: not split (--sun-threshold 0)");
    }
    tool.info("read " + ms(t0, t1) + ", bake " + ms(t1, t2) + ", write " + ms(t2, t3));
    return app::kExitSuccess;
}

} // namespace

int main(int argc, char** argv) {
    return app::guardedMain("dhdr-ibl", [&] { return run(argc, argv); });
}
