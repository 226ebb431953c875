// libdeferred against closed forms and independent references.
#include <OpenImageIO/imagebuf.h>
#include <cmath>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/core/multiple_scattering.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/integrator/lighting.h>
#include <dhdr/deferred/lights/light.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/deferred/scene/camera.h>
#include <dhdr/deferred/scene/lights.h>
#include <dhdr/deferred/scene/scene.h>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <random>

using namespace dhdr;
using OIIO::ImageBuf;

namespace {

const std::string kCornellBox = std::string(DHDR_TESTDATA) + "/cornell_box.gltf";
constexpr double kPiD = 3.14159265358979323846;

const float* px(const ImageBuf& img, int x, int y) {
    return static_cast<const float*>(img.pixeladdr(x, y));
}

float channel(const ImageBuf& img, int x, int y, const char* name) {
    return px(img, x, y)[img.spec().channelindex(name)];
}

// A plane y = 0 (10 m square) and a sphere of radius 0.5 at (0, 1, 0), tessellated finely
// enough (1024 × 512) that its facets are within 1e-5 of the true sphere, with exact normals.
Scene planeAndSphere(bool withSphere = true) {
    Scene scene;
    scene.materials.resize(2);
    scene.materials[0].name = "floor";
    scene.materials[0].baseColor = glm::vec3(0.5f, 0.25f, 0.125f);
    scene.materials[0].roughness = 0.75f;
    scene.materials[0].metallic = 0.0f;
    scene.materials[1].name = "ball";
    scene.materials[1].emission = glm::vec3(2.0f, 3.0f, 4.0f);
    scene.objectNames = {"plane", "sphere"};
    Mesh plane;
    plane.positions = {{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}};
    plane.normals.assign(4, glm::vec3(0, 1, 0));
    plane.triangles = {{0, 2, 1}, {0, 3, 2}};
    scene.meshes.push_back(plane);
    if (!withSphere) return scene;
    Mesh sphere;
    sphere.material = 1;
    sphere.object = 1;
    const int nu = 1024, nv = 512;
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            const double theta = kPiD * j / nv, phi = 2.0 * kPiD * i / nu;
            const glm::dvec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                               std::sin(theta) * std::sin(phi));
            sphere.normals.emplace_back(n);
            sphere.positions.emplace_back(glm::dvec3(0, 1, 0) + 0.5 * n);
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const unsigned a = unsigned(j * (nu + 1) + i), b = a + 1, c = a + nu + 1, d = c + 1;
            sphere.triangles.push_back({a, c, b});
            sphere.triangles.push_back({b, c, d});
        }
    scene.meshes.push_back(sphere);
    return scene;
}

} // namespace

TEST(GBuffer, AnalyticPlaneAndSphereMatchClosedForm) {
    const Scene scene = planeAndSphere();
    const Camera camera =
        Camera::lookAt({0.0, 1.5, 4.0}, {0.0, 0.8, 0.0}, {0.0, 1.0, 0.0}, glm::radians(40.0));
    GBufferParams params;
    params.width = 96;
    params.height = 64;
    ImageBuf gbuf;
    ASSERT_TRUE(renderGBuffer(gbuf, scene, camera, params));
    const glm::dmat4 view = camera.worldToCamera();
    int sphereChecked = 0, planeChecked = 0, background = 0;
    for (int y = 0; y < params.height; ++y)
        for (int x = 0; x < params.width; ++x) {
            const Ray ray = camera.primaryRay(x, y, params.width, params.height);
            // Closed form: the nearest of the sphere |o + t d − c| = r and the plane y = 0.
            const glm::dvec3 oc = ray.origin - glm::dvec3(0, 1, 0);
            const double b = glm::dot(oc, ray.direction), c = glm::dot(oc, oc) - 0.25;
            const double disc = b * b - c;
            double t = INFINITY;
            glm::dvec3 n(0.0);
            bool onSphere = false;
            if (disc > 0.0) {
                t = -b - std::sqrt(disc);
                onSphere = true;
            }
            const double tPlane = -ray.origin.y / ray.direction.y;
            if (tPlane > 0.0 && tPlane < t) {
                t = tPlane;
                onSphere = false;
            }
            if (!std::isfinite(t)) {
                EXPECT_EQ(channel(gbuf, x, y, "A"), 0.0f);
                EXPECT_TRUE(std::isinf(channel(gbuf, x, y, "Z")));
                ++background;
                continue;
            }
            const glm::dvec3 P = ray.origin + t * ray.direction;
            n = onSphere ? glm::normalize(P - glm::dvec3(0, 1, 0)) : glm::dvec3(0, 1, 0);
            // Grazing rays near the silhouette see the facets, not the sphere: skip them, and
            // pixels whose plane hit is shadowed by the sphere's silhouette in the mesh.
            if (std::abs(glm::dot(n, ray.direction)) < 0.3 || (disc > -0.02 && !onSphere)) continue;
            ASSERT_EQ(channel(gbuf, x, y, "A"), 1.0f);
            const double Z = -(view * glm::dvec4(P, 1.0)).z;
            EXPECT_NEAR(channel(gbuf, x, y, "Z"), Z, 1e-4);
            EXPECT_NEAR(channel(gbuf, x, y, "P.X"), P.x, 1e-4);
            EXPECT_NEAR(channel(gbuf, x, y, "P.Y"), P.y, 1e-4);
            EXPECT_NEAR(channel(gbuf, x, y, "P.Z"), P.z, 1e-4);
            EXPECT_NEAR(channel(gbuf, x, y, "N.X"), n.x, 1e-4);
            EXPECT_NEAR(channel(gbuf, x, y, "N.Y"), n.y, 1e-4);
            EXPECT_NEAR(channel(gbuf, x, y, "N.Z"), n.z, 1e-4);
            EXPECT_EQ(channel(gbuf, x, y, "id.object"), onSphere ? 2.0f : 1.0f);
            if (onSphere) {
                EXPECT_EQ(channel(gbuf, x, y, "emission.G"), 3.0f);
                ++sphereChecked;
            } else {
                EXPECT_EQ(channel(gbuf, x, y, "albedo.R"), 0.5f);
                EXPECT_EQ(channel(gbuf, x, y, "roughness"), 0.75f);
                ++planeChecked;
            }
        }
    EXPECT_GT(sphereChecked, 200);
    EXPECT_GT(planeChecked, 1000);
    EXPECT_GT(background, 100);
}

TEST(GBuffer, HeaderCarriesCameraAndNameTables) {
    const Scene scene = planeAndSphere(false);
    const Camera camera = Camera::lookAt({1, 2, 3}, {0, 0, 0}, {0, 1, 0}, 0.7);
    GBufferParams params;
    params.width = 8;
    params.height = 4;
    ImageBuf gbuf;
    ASSERT_TRUE(renderGBuffer(gbuf, scene, camera, params));
    gbuffer::CameraInfo info;
    std::string error;
    ASSERT_TRUE(gbuffer::readCamera(gbuf.spec(), info, error)) << error;
    EXPECT_NEAR(info.position.x, 1.0, 1e-6);
    EXPECT_NEAR(info.position.y, 2.0, 1e-6);
    EXPECT_NEAR(info.position.z, 3.0, 1e-6);
    // worldToNDC takes the look-at target to the centre of the screen.
    const glm::dvec4 clip = info.worldToNDC * glm::dvec4(0, 0, 0, 1);
    EXPECT_NEAR(clip.x / clip.w, 0.0, 1e-6);
    EXPECT_NEAR(clip.y / clip.w, 0.0, 1e-6);
    const OIIO::ParamValue* names = gbuf.spec().find_attribute("dhdr:objectNames");
    ASSERT_NE(names, nullptr);
    ASSERT_EQ(names->type().numelements() * names->nvalues(), 3);
    EXPECT_EQ(std::string(static_cast<const char* const*>(names->data())[1]), "plane");
}

TEST(SceneLoading, CornellBoxCameraIsThePublishedOne) {
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(kCornellBox, scene, error)) << error;
    ASSERT_EQ(scene.cameras.size(), 1u);
    const Camera& c = scene.cameras[0].camera;
    // (278, 273, −800) mm, not twice that (Assimp 5.2 copies the node translation into
    // aiCamera::mPosition as well).
    EXPECT_NEAR(c.position().x, 0.278, 1e-6);
    EXPECT_NEAR(c.position().y, 0.273, 1e-6);
    EXPECT_NEAR(c.position().z, -0.8, 1e-6);
    // Looking down +z in the world.
    const glm::dvec3 forward = -glm::dvec3(c.cameraToWorld[2]);
    EXPECT_NEAR(forward.z, 1.0, 1e-6);
    // 35 mm lens on 25 mm film.
    EXPECT_NEAR(c.yfov, 2.0 * std::atan(12.5 / 35.0), 1e-6);
}

TEST(SceneLoading, CornellBoxMaterialsAndObjects) {
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(kCornellBox, scene, error)) << error;
    EXPECT_EQ(scene.objectNames.size(), 8u);
    const Material* light = nullptr;
    const Material* red = nullptr;
    for (const Material& m : scene.materials) {
        if (m.name == "light") light = &m;
        if (m.name == "red") red = &m;
    }
    ASSERT_TRUE(light && red);
    // emissiveFactor (1, 12/17, 4/17) × KHR_materials_emissive_strength 17, which Assimp 5.2
    // drops and the loader reads from the file itself.
    EXPECT_NEAR(light->emission.r, 17.0f, 1e-4);
    EXPECT_NEAR(light->emission.g, 12.0f, 1e-4);
    EXPECT_NEAR(light->emission.b, 4.0f, 1e-4);
    EXPECT_NEAR(red->baseColor.r, 0.63f, 1e-6);
    EXPECT_EQ(red->metallic, 0.0f);
    EXPECT_NEAR(red->roughness, 0.9f, 1e-6);
    const glm::dvec3 lo = scene.boundsMin(), hi = scene.boundsMax();
    EXPECT_NEAR(lo.x, 0.0, 1e-6);
    EXPECT_NEAR(hi.x, 0.556, 1e-6);
    EXPECT_NEAR(hi.y, 0.5488, 1e-6);
    EXPECT_NEAR(hi.z, 0.5592, 1e-6);
}

TEST(SceneLoading, CornellBoxLightsKeepTheirGltfUnits) {
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(kCornellBox, scene, error)) << error;
    ASSERT_EQ(scene.lights.size(), 2u);
    const Light& point = scene.lights[0];
    EXPECT_EQ(point.type, LightType::Point);
    EXPECT_NEAR(point.position.x, 0.278f, 1e-6);
    EXPECT_NEAR(point.position.y, 0.45f, 1e-6);
    EXPECT_NEAR(point.position.z, 0.2795f, 1e-6);
    // Intensity and colour apart (Assimp 5.2 multiplies them) and the range (it drops it).
    EXPECT_NEAR(point.intensity, 0.35f, 1e-6);
    EXPECT_NEAR(point.color.g, 0.85f, 1e-6);
    EXPECT_NEAR(point.range, 2.0f, 1e-6);
    const Light& spot = scene.lights[1];
    EXPECT_EQ(spot.type, LightType::Spot);
    const glm::vec3 expected = glm::normalize(glm::vec3(0.35f, -0.6f, 0.72f));
    EXPECT_NEAR(spot.direction.x, expected.x, 1e-5);
    EXPECT_NEAR(spot.direction.y, expected.y, 1e-5);
    EXPECT_NEAR(spot.direction.z, expected.z, 1e-5);
    EXPECT_NEAR(spot.outerConeAngle, 0.55f, 1e-6);
    EXPECT_NEAR(spot.innerConeAngle, 0.35f, 1e-6);
}

namespace {

std::string writeTemp(const std::string& name, const std::string& text) {
    const auto path = std::filesystem::temp_directory_path() / ("dhdr_test_" + name);
    std::ofstream(path) << text;
    return path.string();
}

} // namespace

TEST(SceneLoading, GltfFieldOfViewIsYfovWhateverTheAspect) {
    // One triangle and a camera with aspectRatio 1.5 and yfov 0.5: Assimp 5.2 reports
    // mHorizontalFOV = 0.75 (yfov × aspect); the camera must still have yfov 0.5.
    const std::string gltf = R"({
      "asset": {"version": "2.0"}, "scene": 0,
      "scenes": [{"nodes": [0, 1]}],
      "nodes": [{"mesh": 0, "name": "tri"},
                {"camera": 0, "name": "wide", "translation": [1, 2, 3]}],
      "cameras": [{"type": "perspective",
                   "perspective": {"yfov": 0.5, "aspectRatio": 1.5, "znear": 0.1}}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, 0], "max": [1, 1, 0]}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "buffers": [{"byteLength": 36,
        "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]
    })";
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(writeTemp("wide.gltf", gltf), scene, error)) << error;
    ASSERT_EQ(scene.cameras.size(), 1u);
    EXPECT_NEAR(scene.cameras[0].camera.yfov, 0.5, 1e-6);
    EXPECT_NEAR(scene.cameras[0].aspect, 1.5, 1e-6);
    EXPECT_NEAR(scene.cameras[0].camera.position().x, 1.0, 1e-6);
    EXPECT_NEAR(scene.cameras[0].camera.position().z, 3.0, 1e-6);
    // No normals in the file: flat normals are generated (glTF §3.7.2.1).
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_NEAR(std::abs(scene.meshes[0].normals[0].z), 1.0f, 1e-6);
}

TEST(SceneLoading, BaseColourTextureIsSampledWithGltfUvs) {
    // A unit quad facing +z with glTF UVs (0, 0) at its top-left corner, textured with a 2×2
    // PNG: red, green / blue, grey 128. Seen face-on by a 2×2 camera, each pixel centre falls
    // on one texel centre.
    const auto dir = std::filesystem::temp_directory_path();
    OIIO::ImageBuf png(OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::UINT8));
    const unsigned char texels[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {128, 128, 128}};
    for (int i = 0; i < 4; ++i) {
        const float rgb[3] = {texels[i][0] / 255.0f, texels[i][1] / 255.0f, texels[i][2] / 255.0f};
        png.setpixel(i % 2, i / 2, rgb);
    }
    ASSERT_TRUE(png.write((dir / "dhdr_test_texels.png").string()));
    const float positions[4][3] = {{0, 1, 0}, {1, 1, 0}, {1, 0, 0}, {0, 0, 0}};
    const float uvs[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const unsigned short indices[6] = {0, 3, 2, 0, 2, 1};
    {
        std::ofstream bin(dir / "dhdr_test_quad.bin", std::ios::binary);
        bin.write(reinterpret_cast<const char*>(positions), sizeof positions);
        bin.write(reinterpret_cast<const char*>(uvs), sizeof uvs);
        bin.write(reinterpret_cast<const char*>(indices), sizeof indices);
    }
    const std::string gltf = R"({
      "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
      "nodes": [{"mesh": 0, "name": "quad"}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1},
                                  "indices": 2, "material": 0}]}],
      "materials": [{"name": "textured", "pbrMetallicRoughness": {
          "baseColorTexture": {"index": 0}, "metallicFactor": 0}}],
      "textures": [{"source": 0}], "images": [{"uri": "dhdr_test_texels.png"}],
      "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
         "min": [0, 0, 0], "max": [1, 1, 0]},
        {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
        {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                      {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                      {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
      "buffers": [{"byteLength": 92, "uri": "dhdr_test_quad.bin"}]
    })";
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(writeTemp("quad.gltf", gltf), scene, error)) << error;
    ASSERT_EQ(scene.textures.size(), 1u);
    const Camera camera =
        Camera::lookAt({0.5, 0.5, 1.0}, {0.5, 0.5, 0.0}, {0.0, 1.0, 0.0}, 2.0 * std::atan(0.5));
    GBufferParams params;
    params.width = 2;
    params.height = 2;
    ImageBuf gbuf;
    ASSERT_TRUE(renderGBuffer(gbuf, scene, camera, params));
    // 128/255 decoded from sRGB.
    const float grey = float(std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4));
    const float expected[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {grey, grey, grey}};
    for (int i = 0; i < 4; ++i) {
        EXPECT_NEAR(channel(gbuf, i % 2, i / 2, "albedo.R"), expected[i][0], 1e-5) << i;
        EXPECT_NEAR(channel(gbuf, i % 2, i / 2, "albedo.G"), expected[i][1], 1e-5) << i;
        EXPECT_NEAR(channel(gbuf, i % 2, i / 2, "albedo.B"), expected[i][2], 1e-5) << i;
    }
}

TEST(SceneLoading, ObjQuadsAreTriangulated) {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(writeTemp("quad.obj", obj), scene, error)) << error;
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.meshes[0].triangles.size(), 2u);
    EXPECT_NEAR(std::abs(scene.meshes[0].normals[0].z), 1.0f, 1e-6);
}

TEST(SceneLoading, MissingAndBrokenFilesAreErrors) {
    Scene scene;
    std::string error;
    EXPECT_FALSE(loadScene("/nonexistent/scene.gltf", scene, error));
    EXPECT_NE(error.find("/nonexistent/scene.gltf"), std::string::npos);
    EXPECT_FALSE(loadScene(writeTemp("broken.gltf", "{\"asset\": "), scene, error));
    EXPECT_NE(error.find("broken.gltf"), std::string::npos);
}

TEST(Lights, ParsesEveryTypeWithDefaults) {
    std::vector<Light> lights;
    std::string error;
    ASSERT_TRUE(parseLights(R"({"lights": [
        {"type": "point", "position": [1, 2, 3], "intensity": 5, "range": 2},
        {"type": "spot", "position": [0, 1, 0], "direction": [0, -2, 0],
         "innerConeAngle": 0.2, "outerConeAngle": 0.4},
        {"type": "directional", "direction": [0, 0, -1], "color": [1, 0.5, 0.25]},
        {"type": "ambient", "intensity": 0.1}]})",
                            lights, error))
        << error;
    ASSERT_EQ(lights.size(), 4u);
    EXPECT_EQ(lights[0].range, 2.0f);
    EXPECT_EQ(lights[1].direction, glm::vec3(0, -1, 0)); // normalized
    EXPECT_TRUE(std::isinf(lights[1].range));
    EXPECT_EQ(lights[2].color.g, 0.5f);
    EXPECT_EQ(lights[3].type, LightType::Ambient);
    // Round trip.
    std::vector<Light> again;
    ASSERT_TRUE(parseLights(formatLights(lights), again, error)) << error;
    EXPECT_EQ(again[1].outerConeAngle, 0.4f);
}

TEST(Lights, ErrorsNameTheLightAndField) {
    std::vector<Light> lights;
    std::string error;
    EXPECT_FALSE(parseLights(R"({"lights": [{"type": "point", "position": [0, 0, 0]},
                                            {"type": "point", "position": [0, 0, 0],
                                             "range": -1}]})",
                             lights, error));
    EXPECT_EQ(error, "light 1: \"range\" must be a positive number");
    EXPECT_FALSE(
        parseLights(R"({"lights": [{"type": "spot", "direction": [0, 0, 1]}]})", lights, error));
    EXPECT_EQ(error, "light 0: \"position\" is required");
    EXPECT_FALSE(parseLights(R"([{"type": "laser"}])", lights, error));
    EXPECT_NE(error.find("light 0: \"type\""), std::string::npos);
    EXPECT_FALSE(parseLights(R"({"lights": [{"type": "ambient"}, 7]})", lights, error));
    EXPECT_EQ(error, "light 1: not an object");
    EXPECT_FALSE(parseLights(R"({"lights": [[]]})", lights, error));
    EXPECT_EQ(error, "light 0: not an object");
    EXPECT_FALSE(parseLights(R"({"lamps": []})", lights, error));
    EXPECT_EQ(error, "unknown key \"lamps\" at the top level (a lights file has \"lights\")");
    EXPECT_FALSE(parseLights(R"({"$comment": "none"})", lights, error));
    EXPECT_EQ(error, "no \"lights\" array");
    EXPECT_FALSE(parseLights("{\"lights\": [", lights, error));
    EXPECT_NE(error.find("not valid JSON"), std::string::npos);
}

// Issue 21: a misspelt or foreign key is an error naming the key and the light, not a light
// silently left at its defaults.
TEST(Lights, UnknownKeysAreErrors) {
    std::vector<Light> lights;
    std::string error;
    EXPECT_FALSE(parseLights(R"({"lights": [{"type": "ambient"},
        {"type": "point", "name": "bulb", "position": [0, 0, 0], "colour": [1, 0, 0]}]})",
                             lights, error));
    EXPECT_EQ(error, "light 1 (point \"bulb\"): unknown key \"colour\" (did you mean \"color\"?)");
    EXPECT_FALSE(parseLights(R"([{"type": "spot", "position": [0, 0, 0], "direction": [0, 0, 1],
                                  "rnage": 2}])",
                             lights, error));
    EXPECT_EQ(error, "light 0 (spot): unknown key \"rnage\" (did you mean \"range\"?)");
    EXPECT_FALSE(parseLights(R"([{"type": "point", "position": [0, 0, 0], "brightness": 2}])",
                             lights, error));
    EXPECT_EQ(error, "light 0 (point): unknown key \"brightness\"");
    // A key of another type: a point light given a direction was meant to be a spot.
    EXPECT_FALSE(parseLights(
        R"([{"type": "point", "position": [0, 0, 0], "direction": [0, 0, 1]}])", lights, error));
    EXPECT_EQ(error, "light 0 (point): \"direction\" does not apply to a point light (only to "
                     "spot, directional or rectangle)");
    EXPECT_FALSE(parseLights(R"({"lights": [], "version": 2})", lights, error));
    EXPECT_EQ(error, "unknown key \"version\" at the top level (a lights file has \"lights\")");
    // Comments and a schema reference are allowed, as in the channel map.
    EXPECT_TRUE(parseLights(R"({"$schema": "lights.schema.json", "$comment": "x",
        "lights": [{"type": "ambient", "$comment": "fill"}]})",
                            lights, error))
        << error;
    // What formatLights writes for every type reads back.
    Light rect;
    rect.type = LightType::Rectangle;
    rect.width = rect.height = 1.0f;
    rect.direction = glm::vec3(0, -1, 0);
    rect.up = glm::vec3(0, 0, 1);
    Light sphere;
    sphere.type = LightType::Sphere;
    sphere.radius = 0.5f;
    Light spot;
    spot.type = LightType::Spot;
    Light env;
    env.type = LightType::Environment;
    env.image = "sky.exr";
    Light sun;
    sun.type = LightType::Directional;
    sun.angle = 0.53f * 3.14159265f / 180.0f;
    std::vector<Light> again;
    ASSERT_TRUE(parseLights(formatLights({rect, sphere, spot, env, sun}), again, error)) << error;
    ASSERT_EQ(again.size(), 5u);
    EXPECT_NEAR(again[4].angle, sun.angle, 1e-7f);
    // A sun's angle: degrees in [0, 180), for directional lights only.
    ASSERT_TRUE(parseLights(R"([{"type": "directional", "direction": [0, -1, 0], "angle": 4}])",
                            again, error))
        << error;
    EXPECT_NEAR(again[0].angle, 4.0f * 3.14159265f / 180.0f, 1e-7f);
    EXPECT_FALSE(parseLights(R"([{"type": "directional", "direction": [0, -1, 0], "angle": -1}])",
                             again, error));
    EXPECT_NE(error.find("\"angle\" must be in [0, 180) degrees"), std::string::npos) << error;
    EXPECT_FALSE(
        parseLights(R"([{"type": "point", "position": [0, 0, 0], "angle": 1}])", again, error));
    EXPECT_NE(error.find("\"angle\" does not apply to a point light"), std::string::npos) << error;
}

// ---- BRDF -------------------------------------------------------------------------------

namespace {

// ∫ over the hemisphere of g(ω) dω by a midpoint rule in (cos θ, φ).
template <typename F>
double hemisphereIntegral(F g, int n = 1024) {
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n / 4; ++j) {
            const double cosTheta = (i + 0.5) / n, phi = 2.0 * kPiD * (j + 0.5) / (n / 4);
            const double sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
            sum += g(glm::vec3(float(sinTheta * std::cos(phi)), float(sinTheta * std::sin(phi)),
                               float(cosTheta)));
        }
    return sum * (1.0 / n) * (2.0 * kPiD / (n / 4));
}

} // namespace

TEST(Brdf, GgxDistributionIsNormalized) {
    // ∫ D(h) (n·h) dω_h = 1 (Walter et al. 2007 eq. 4).
    for (float alpha : {0.1f, 0.3f, 0.6f, 1.0f}) {
        const double integral = hemisphereIntegral(
            [&](const glm::vec3& h) { return ggxDistribution(h.z, alpha) * h.z; }, 4096);
        EXPECT_NEAR(integral, 1.0, 2e-3) << "alpha " << alpha;
    }
}

TEST(Brdf, SpecularLobeNeverReflectsMoreThanItReceives) {
    // White furnace on a white metal (F = 1): the single-scattering GGX lobe (evaluateBrdf
    // without the multiple-scattering lobe, which test_multiple_scattering checks) loses
    // energy with roughness but never gains any.
    const glm::vec3 N(0, 0, 1);
    for (float roughness : {0.2f, 0.5f, 0.8f, 1.0f})
        for (float cosV : {1.0f, 0.7f, 0.3f}) {
            PbrSurface s;
            s.baseColor = glm::vec3(1.0f);
            s.roughness = roughness;
            s.metallic = 1.0f;
            const glm::vec3 V(std::sqrt(1 - cosV * cosV), 0.0f, cosV);
            const double albedo = hemisphereIntegral([&](const glm::vec3& L) {
                return (evaluateBrdf(s, N, V, L).g - multipleScatteringBrdf(s, cosV, L.z).g) * L.z;
            });
            EXPECT_LE(albedo, 1.0 + 2e-3) << roughness << " " << cosV;
            if (roughness <= 0.2f) {
                EXPECT_GT(albedo, 0.97) << cosV;
            }
        }
}

TEST(Brdf, RoughMetalAlbedoAtNormalIncidenceIsOneMinusLnTwo) {
    // At α = 1, D = 1/π and V = 1 / (2 (N·L + N·V)); at N·V = 1 the directional albedo is
    // ∫₀¹ μ / (μ + 1) dμ = 1 − ln 2 for the single-scattering lobe.
    PbrSurface s;
    s.baseColor = glm::vec3(1.0f);
    s.roughness = 1.0f;
    s.metallic = 1.0f;
    const glm::vec3 N(0, 0, 1);
    const double albedo = hemisphereIntegral([&](const glm::vec3& L) {
        return (evaluateBrdf(s, N, N, L).g - multipleScatteringBrdf(s, 1.0f, L.z).g) * L.z;
    });
    EXPECT_NEAR(albedo, 1.0 - std::log(2.0), 1e-3);
}

TEST(Brdf, DielectricConservesEnergyAwayFromGrazing) {
    // glTF's fresnel_mix weights the diffuse lobe by 1 − F(V·H) per light direction, which
    // overshoots at grazing views (docs/lighting.md); from N·V ≥ 0.7 it stays within 0.2 %.
    const glm::vec3 N(0, 0, 1);
    for (float roughness : {0.2f, 0.5f, 1.0f})
        for (float cosV : {1.0f, 0.7f}) {
            PbrSurface s;
            s.baseColor = glm::vec3(1.0f);
            s.roughness = roughness;
            const glm::vec3 V(std::sqrt(1 - cosV * cosV), 0.0f, cosV);
            const double albedo = hemisphereIntegral(
                [&](const glm::vec3& L) { return evaluateBrdf(s, N, V, L).g * L.z; });
            EXPECT_LE(albedo, 1.0 + 2e-3) << roughness << " " << cosV;
            EXPECT_GT(albedo, 0.95) << roughness << " " << cosV;
        }
}

TEST(Brdf, LambertDiffuseWithoutFresnelIsAlbedoOverPi) {
    // For a dielectric the diffuse lobe is (1 − F) c / π; at normal incidence, and with
    // L = V = N, F = F0 = 0.04 and the specular term is D(1) V F with D(1) = 1/(π α²), plus
    // the multiple-scattering lobe.
    PbrSurface s;
    s.baseColor = glm::vec3(0.5f);
    s.roughness = 1.0f;
    const glm::vec3 N(0, 0, 1);
    const glm::vec3 f = evaluateBrdf(s, N, N, N);
    const double diffuse = 0.96 * 0.5 / kPiD;
    const double specular = 0.04 * (1.0 / kPiD) * 0.25; // V = 1/(4 N·L N·V) at α = 1
    EXPECT_NEAR(f.r, diffuse + specular + multipleScatteringBrdf(s, 1.0f, 1.0f).r, 1e-6);
}

// ---- lighting ---------------------------------------------------------------------------

namespace {

// The glTF BRDF written out again in double precision, term by term, for the reference; the
// multiple-scattering lobe from the library (test_multiple_scattering checks it).
double referenceRadiance(const glm::dvec3& P, const glm::dvec3& eye, const glm::dvec3& lightPos,
                         double intensity, double range, double albedo, double roughness) {
    const glm::dvec3 N(0, 1, 0);
    const glm::dvec3 V = glm::normalize(eye - P);
    const glm::dvec3 toLight = lightPos - P;
    const double d = glm::length(toLight);
    const glm::dvec3 L = toLight / d;
    const glm::dvec3 H = glm::normalize(L + V);
    const double NL = glm::dot(N, L), NV = glm::dot(N, V), NH = glm::dot(N, H);
    const double VH = glm::dot(V, H);
    const double a = roughness * roughness, a2 = a * a;
    const double D = a2 / (kPiD * std::pow(NH * NH * (a2 - 1.0) + 1.0, 2.0));
    const double Vis =
        0.5 / (NL * std::sqrt(NV * NV * (1 - a2) + a2) + NV * std::sqrt(NL * NL * (1 - a2) + a2));
    const double F = 0.04 + 0.96 * std::pow(1.0 - VH, 5.0);
    const double window = std::pow(std::max(0.0, 1.0 - std::pow(d / range, 4.0)), 2.0);
    // Irradiance from a point source on a plane at height h: E = I cos θ / d² = I h / d³.
    const double E = intensity * window * NL / (d * d);
    PbrSurface s;
    s.baseColor = glm::vec3(float(albedo));
    s.roughness = float(roughness);
    const double ms = multipleScatteringBrdf(s, float(NV), float(NL)).r;
    return ((1.0 - F) * albedo / kPiD + D * Vis * F + ms) * E;
}

ImageBuf renderPlane(int w, int h, Camera& camera) {
    const Scene scene = planeAndSphere(false);
    camera = Camera::lookAt({0.0, 2.0, 3.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 0.9);
    GBufferParams params;
    params.width = w;
    params.height = h;
    ImageBuf gbuf;
    renderGBuffer(gbuf, scene, camera, params);
    return gbuf;
}

} // namespace

TEST(Lighting, PlaneUnderOnePointLightMatchesClosedForm) {
    Camera camera;
    const ImageBuf gbuf = renderPlane(64, 48, camera);
    Light light;
    light.position = glm::vec3(0.3f, 1.2f, -0.4f);
    light.intensity = 10.0f;
    light.range = 3.0f;
    ImageBuf hdr;
    ASSERT_TRUE(shadeGBuffer(hdr, gbuf, {{light}}));
    int checked = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            if (channel(gbuf, x, y, "A") == 0.0f) continue;
            const glm::dvec3 P(channel(gbuf, x, y, "P.X"), channel(gbuf, x, y, "P.Y"),
                               channel(gbuf, x, y, "P.Z"));
            // albedo.R of the floor is 0.5, roughness 0.75.
            const double expected = referenceRadiance(
                P, camera.position(), glm::dvec3(light.position), 10.0, 3.0, 0.5, 0.75);
            EXPECT_NEAR(px(hdr, x, y)[0], expected, 1e-5 + 1e-4 * expected) << x << "," << y;
            EXPECT_EQ(px(hdr, x, y)[3], 1.0f);
            if (expected > 0.0) ++checked;
        }
    EXPECT_GT(checked, 500);
}

TEST(Lighting, AmbientAndDirectionalLights) {
    Camera camera;
    const ImageBuf gbuf = renderPlane(16, 12, camera);
    Light ambient;
    ambient.type = LightType::Ambient;
    ambient.intensity = 2.0f;
    ImageBuf hdr;
    ASSERT_TRUE(shadeGBuffer(hdr, gbuf, {{ambient}}));
    // La (c (1 − F0) T(N·V) + the specular albedo at N·V) for the floor's red channel,
    // c = 0.5, roughness 0.75 (T: the diffuse layer's Fresnel transmission).
    {
        const glm::dvec3 P(channel(gbuf, 8, 10, "P.X"), channel(gbuf, 8, 10, "P.Y"),
                           channel(gbuf, 8, 10, "P.Z"));
        const float NdotV = float(glm::normalize(camera.position() - P).y);
        PbrSurface s;
        s.baseColor = glm::vec3(0.5f);
        s.roughness = 0.75f;
        const glm::vec2 e = ggxAlbedoTerms(NdotV, 0.75f);
        const double specular = 0.04 * (e.y - e.x) + e.x + multipleScatteringAlbedo(s, NdotV).r;
        EXPECT_NEAR(px(hdr, 8, 10)[0],
                    2.0 * (0.5 * 0.96 * diffuseFresnelTransmission(NdotV) + specular), 1e-5);
    }

    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::vec3(0.0f, -1.0f, 0.0f);
    sun.intensity = 3.0f;
    ASSERT_TRUE(shadeGBuffer(hdr, gbuf, {{sun}}));
    const glm::dvec3 P(channel(gbuf, 8, 10, "P.X"), channel(gbuf, 8, 10, "P.Y"),
                       channel(gbuf, 8, 10, "P.Z"));
    // A directional light is a point light infinitely far straight up: E = 3 lux.
    const glm::dvec3 far = P + glm::dvec3(0.0, 1e4, 0.0);
    const double expected =
        referenceRadiance(P, camera.position(), far, 3.0e8, INFINITY, 0.5, 0.75);
    EXPECT_NEAR(px(hdr, 8, 10)[0], expected, 1e-4 * expected);
}

TEST(Lighting, SpotConeEdges) {
    Light spot;
    spot.type = LightType::Spot;
    spot.position = glm::vec3(0, 1, 0);
    spot.direction = glm::vec3(0, -1, 0);
    spot.innerConeAngle = 0.2f;
    spot.outerConeAngle = 0.4f;
    auto at = [&](double angle) {
        const glm::vec3 P(float(std::tan(angle)), 0.0f, 0.0f);
        return incidentLight(spot, P).illuminance.r;
    };
    EXPECT_GT(at(0.19), 0.0f);
    EXPECT_NEAR(at(0.19) * (1.0 + std::pow(std::tan(0.19), 2)), 1.0, 1e-5); // I / d², full
    EXPECT_EQ(at(0.41), 0.0f);
    EXPECT_GT(at(0.3), 0.0f);
    EXPECT_LT(at(0.3) * (1.0 + std::pow(std::tan(0.3), 2)), 1.0);
}

TEST(Lighting, RangeWindowReachesExactlyZero) {
    EXPECT_EQ(rangeWindow(2.0f, 2.0f), 0.0f);
    EXPECT_EQ(rangeWindow(2.5f, 2.0f), 0.0f);
    EXPECT_EQ(rangeWindow(0.0f, 2.0f), 1.0f);
    EXPECT_NEAR(rangeWindow(1.0f, 2.0f), (1.0 - 1.0 / 16.0) * (1.0 - 1.0 / 16.0), 1e-7);
}

TEST(Lighting, MissingChannelIsNamed) {
    ImageBuf rgba(OIIO::ImageSpec(4, 4, 4, OIIO::TypeDesc::FLOAT));
    ImageBuf hdr;
    EXPECT_FALSE(shadeGBuffer(hdr, rgba, {{}}));
    EXPECT_NE(hdr.geterror().find("no channel 'Z'"), std::string::npos);
}

TEST(Lighting, ScreenBoundedEqualsBruteForceOnCornellBoxWith200Lights) {
    Scene scene;
    std::string error;
    ASSERT_TRUE(loadScene(kCornellBox, scene, error)) << error;
    GBufferParams params;
    params.width = 200;
    params.height = 150;
    ImageBuf gbuf;
    ASSERT_TRUE(renderGBuffer(gbuf, scene, scene.cameras[0].camera, params));

    std::mt19937 rng(2024);
    auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * (rng() / 4294967296.0); };
    std::vector<Light> lights;
    for (int i = 0; i < 200; ++i) {
        Light l;
        l.type = i % 4 == 3 ? LightType::Spot : LightType::Point;
        l.position = glm::vec3(uniform(0.0, 0.556), uniform(0.0, 0.549), uniform(0.0, 0.559));
        l.color = glm::vec3(uniform(0.2, 1.0), uniform(0.2, 1.0), uniform(0.2, 1.0));
        l.intensity = float(uniform(0.001, 0.02));
        l.range = float(uniform(0.03, 0.15));
        l.direction =
            glm::normalize(glm::vec3(uniform(-1.0, 1.0), uniform(-1.0, 0.0), uniform(-1.0, 1.0)));
        l.innerConeAngle = 0.3f;
        l.outerConeAngle = 0.6f;
        lights.push_back(l);
    }
    Light ambient;
    ambient.type = LightType::Ambient;
    ambient.intensity = 0.01f;
    lights.push_back(ambient);

    ImageBuf culled, brute;
    LightingStats culledStats, bruteStats;
    LightingParams p;
    ASSERT_TRUE(shadeGBuffer(culled, gbuf, {lights}, p, {}, 0, &culledStats));
    p.bruteForce = true;
    ASSERT_TRUE(shadeGBuffer(brute, gbuf, {lights}, p, {}, 0, &bruteStats));
    double maxRelative = 0.0;
    for (int y = 0; y < params.height; ++y)
        for (int x = 0; x < params.width; ++x)
            for (int c = 0; c < 4; ++c) {
                const double a = px(culled, x, y)[c], b = px(brute, x, y)[c];
                maxRelative = std::max(maxRelative, std::abs(a - b) / std::max(std::abs(b), 1e-6));
            }
    EXPECT_LE(maxRelative, 1e-5);
    // And the culling did cull: far fewer evaluations than 201 per pixel.
    EXPECT_EQ(bruteStats.lightEvaluations, bruteStats.coveredPixels * 201);
    EXPECT_LT(culledStats.lightEvaluations * 4, bruteStats.lightEvaluations);
}
