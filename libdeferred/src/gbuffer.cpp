#include <OpenImageIO/imageio.h>
#include <cstring>
#include <dhdr/deferred/gbuffer.h>

namespace dhdr::gbuffer {

std::vector<std::string> channelNames() {
    std::vector<std::string> names = {kCoverage, kDepth};
    for (const char* c : kPosition)
        names.push_back(c);
    for (const char* c : kNormal)
        names.push_back(c);
    for (const char* c : kAlbedo)
        names.push_back(c);
    names.push_back(kRoughness);
    names.push_back(kMetallic);
    for (const char* c : kEmission)
        names.push_back(c);
    names.push_back(kObjectId);
    names.push_back(kMaterialId);
    return names;
}

namespace {

// Index of the first of `names` in `spec`, checking that the others follow it.
bool findGroup(const OIIO::ImageSpec& spec, const char* const* names, int count, int& index,
               std::string& missing) {
    index = spec.channelindex(names[0]);
    for (int i = 0; i < count; ++i) {
        if (index < 0 || spec.channelindex(names[i]) != index + i) {
            missing = spec.channelindex(names[i]) < 0 ? names[i]
                                                      : std::string(names[i]) + " (out of order)";
            index = -1;
            return false;
        }
    }
    return true;
}

} // namespace

bool findLayout(const OIIO::ImageSpec& spec, Layout& layout, std::string& missing) {
    layout = Layout{};
    const char* const coverage[] = {kCoverage};
    const char* const depth[] = {kDepth};
    const char* const roughness[] = {kRoughness};
    const char* const metallic[] = {kMetallic};
    if (!findGroup(spec, coverage, 1, layout.coverage, missing) ||
        !findGroup(spec, depth, 1, layout.depth, missing) ||
        !findGroup(spec, kPosition, 3, layout.position, missing) ||
        !findGroup(spec, kNormal, 3, layout.normal, missing) ||
        !findGroup(spec, kAlbedo, 3, layout.albedo, missing) ||
        !findGroup(spec, roughness, 1, layout.roughness, missing) ||
        !findGroup(spec, metallic, 1, layout.metallic, missing))
        return false;
    std::string ignored;
    findGroup(spec, kEmission, 3, layout.emission, ignored);
    layout.objectId = spec.channelindex(kObjectId);
    layout.materialId = spec.channelindex(kMaterialId);
    return true;
}

namespace {

bool getMatrix(const OIIO::ImageSpec& spec, const char* name, glm::dmat4& m) {
    const OIIO::ParamValue* p = spec.find_attribute(name, OIIO::TypeMatrix44);
    if (!p) return false;
    // OpenEXR's M44f is row-major for row vectors; read as glm's column-major for column
    // vectors, the same 16 numbers are the same transform.
    const float* f = static_cast<const float*>(p->data());
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            m[c][r] = f[4 * c + r];
    return true;
}

void setMatrix(OIIO::ImageSpec& spec, const char* name, const glm::dmat4& m) {
    float f[16];
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            f[4 * c + r] = float(m[c][r]);
    spec.attribute(name, OIIO::TypeMatrix44, f);
}

} // namespace

bool readCamera(const OIIO::ImageSpec& spec, CameraInfo& camera) {
    if (!getMatrix(spec, "worldToCamera", camera.worldToCamera) ||
        !getMatrix(spec, "worldToNDC", camera.worldToNDC))
        return false;
    camera.position = glm::dvec3(glm::inverse(camera.worldToCamera)[3]);
    return true;
}

void writeCamera(OIIO::ImageSpec& spec, const CameraInfo& camera) {
    setMatrix(spec, "worldToCamera", camera.worldToCamera);
    setMatrix(spec, "worldToNDC", camera.worldToNDC);
}

} // namespace dhdr::gbuffer
