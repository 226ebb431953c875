// Uses dhdr as an installed library: one lighting call, one tone-mapping call, and the
// lit frame streamed to a file and back through the io library's strip pipeline.
#include <cmath>
#include <cstdio>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/io/image_output.h>
#include <dhdr/io/strip_pipeline.h>
#include <dhdr/io/strip_reader.h>
#include <dhdr/tonemap/metering.h>
#include <dhdr/tonemap/tone_map.h>
#include <filesystem>
#include <string>
#include <unistd.h>

int main() {
    // A white square facing a camera, lit by a point light in front of it.
    dhdr::Scene scene;
    dhdr::Material white;
    white.name = "white";
    white.metallic = 0.0f;
    scene.materials.push_back(white);
    scene.objectNames = {"square"};
    dhdr::Mesh m;
    m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.meshes.push_back(m);
    const dhdr::Camera camera = dhdr::Camera::lookAt({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 0.5);
    dhdr::GBufferParams gp;
    gp.width = 32;
    gp.height = 32;
    OIIO::ImageBuf gbuffer, hdr, ldr;
    if (!dhdr::renderGBuffer(gbuffer, scene, camera, gp)) return 1;
    dhdr::Light light;
    light.type = dhdr::LightType::Point;
    light.position = {0.0f, 0.0f, 1.0f};
    light.intensity = 1.0f;
    const std::vector<dhdr::Light> lights = {light};
    if (!dhdr::shadeGBuffer(hdr, gbuffer, {lights})) {
        std::fprintf(stderr, "%s\n", hdr.geterror().c_str());
        return 1;
    }
    // Metered whole, tone-mapped strip by strip into a file, then read back.
    dhdr::LuminanceStats stats;
    if (!dhdr::meter(stats, hdr)) return 1;
    dhdr::ToneMapParams mapping;
    mapping.stats = &stats;
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("dhdr_consumer_" + std::to_string(getpid()) + ".exr"))
                                 .string();
    dhdr::ImageFileOutput file(path);
    if (!file.open(hdr.spec(), {OIIO::TypeDesc::HALF})) return 1;
    dhdr::StripPipelineParams strips;
    strips.rows = 8;
    dhdr::StripPipeline pipeline(hdr.roi(), strips);
    pipeline.setOutput(file);
    const bool streamed = pipeline.run([&](dhdr::StripContext& strip) {
        return dhdr::toneMap(*strip.output, hdr, mapping, strip.rows);
    });
    if (!streamed || !file.commit()) {
        std::fprintf(stderr, "%s %s\n", pipeline.error().c_str(), file.geterror().c_str());
        return 1;
    }
    dhdr::StripReader reader;
    std::string error;
    if (!reader.open(path, 0, 0, 4, 0, error) || !reader.read(0, 32, ldr, error)) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 1;
    }
    std::filesystem::remove(path);
    float centre[4];
    ldr.getpixel(16, 16, centre);
    std::printf("dhdr %s: centre %.4f %.4f %.4f\n", DHDR_FOUND_VERSION, centre[0], centre[1],
                centre[2]);
    return centre[0] > 0.0f && centre[0] <= 1.0f && std::isfinite(centre[0]) ? 0 : 1;
}
