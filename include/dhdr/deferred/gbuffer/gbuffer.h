// The G-buffer contract (docs/gbuffer.md): channel names and types, the camera in the header,
// and how a stage finds the channels it needs in a file someone else wrote.
#pragma once

#include <OpenImageIO/oiioversion.h>
#include <OpenImageIO/typedesc.h>
#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

OIIO_NAMESPACE_BEGIN
class ImageSpec;
OIIO_NAMESPACE_END

namespace dhdr::gbuffer {

// Channel names, in the order dhdr-gbuffer writes them.
inline constexpr const char* kCoverage = "A";
inline constexpr const char* kDepth = "Z";
inline constexpr const char* kPosition[3] = {"P.X", "P.Y", "P.Z"};
inline constexpr const char* kNormal[3] = {"N.X", "N.Y", "N.Z"};
inline constexpr const char* kGeometricNormal[3] = {"Ng.X", "Ng.Y", "Ng.Z"};
inline constexpr const char* kPositionError = "Perr";
inline constexpr const char* kLift[3] = {"Plift.X", "Plift.Y", "Plift.Z"};
inline constexpr const char* kAlbedo[3] = {"albedo.R", "albedo.G", "albedo.B"};
inline constexpr const char* kRoughness = "roughness";
inline constexpr const char* kMetallic = "metallic";
inline constexpr const char* kOcclusion = "occlusion";
inline constexpr const char* kSpecular[3] = {"specular.R", "specular.G", "specular.B"};
inline constexpr const char* kSpecularWeight = "specularWeight";
inline constexpr const char* kClearcoat = "clearcoat";
inline constexpr const char* kClearcoatRoughness = "clearcoatRoughness";
inline constexpr const char* kClearcoatNormal[3] = {"clearcoatN.X", "clearcoatN.Y", "clearcoatN.Z"};
inline constexpr const char* kSheen[3] = {"sheen.R", "sheen.G", "sheen.B"};
inline constexpr const char* kSheenRoughness = "sheenRoughness";
inline constexpr const char* kTransmission = "transmission";
inline constexpr const char* kAttenuation[3] = {"attenuation.R", "attenuation.G", "attenuation.B"};
inline constexpr const char* kEmission[3] = {"emission.R", "emission.G", "emission.B"};
inline constexpr const char* kObjectId = "id.object";
inline constexpr const char* kMaterialId = "id.material";
inline constexpr const char* kSampleId = "sample.id";
inline constexpr const char* kSampleWeight = "sample.weight";

// The motion layer of a G-buffer rendered with animation (float, after the contract's
// channels; not in kContract, which every G-buffer has): Blender's Vector pass, in pixels with
// y up: X Y = position at the previous frame − position now, Z W = position now − position at
// the next frame (docs/animation.md).
inline constexpr const char* kMotion[4] = {"motion.X", "motion.Y", "motion.Z", "motion.W"};

// Header attribute: SHA-1 of the scene file the G-buffer was rendered from (sceneFingerprint).
inline constexpr const char* kSceneFingerprint = "dhdr:sceneSHA1";

// Header attributes of a G-buffer with a ground plane (dhdr-gbuffer --ground-plane): its
// height (float), and the id.object of its pixels (int), which dhdr-light treats as a shadow
// catcher.
inline constexpr const char* kGroundPlaneY = "dhdr:groundPlaneY";
inline constexpr const char* kShadowCatcher = "dhdr:shadowCatcher";

// Index of each channel within a G-buffer's channel list (of its first component for the
// 3-vectors, whose components must follow in X Y Z / R G B order).
struct Layout {
    int coverage = -1, depth = -1, depthBack = -1, position = -1, normal = -1, albedo = -1;
    int geometricNormal = -1, positionError = -1, lift = -1;
    int roughness = -1, metallic = -1, occlusion = -1, specular = -1, specularWeight = -1;
    int clearcoat = -1, clearcoatRoughness = -1, clearcoatNormal = -1;
    int sheen = -1, sheenRoughness = -1;
    int transmission = -1, attenuation = -1;
    int emission = -1, objectId = -1, materialId = -1;
    int cryptoObject = -1, cryptoMaterial = -1;
    int sampleId = -1, sampleWeight = -1;
};

// Cryptomatte (spec 1.2): one layer of two ranks (id, coverage, id, coverage) for objects and
// one for materials. Ids are MurmurHash3_x86_32 of the UTF-8 name as float (cryptomatteId).
inline constexpr const char* kCryptoObject[4] = {"CryptoObject00.r", "CryptoObject00.g",
                                                 "CryptoObject00.b", "CryptoObject00.a"};
inline constexpr const char* kCryptoMaterial[4] = {"CryptoMaterial00.r", "CryptoMaterial00.g",
                                                   "CryptoMaterial00.b", "CryptoMaterial00.a"};

// The back of a deep sample's depth range; equal to Z for the point samples of a surface.
inline constexpr const char* kDepthBack = "ZBack";

enum class FileType { Half, Float, Uint };
enum class Need {
    Required, // dhdr-light rejects a G-buffer without it
    Optional, // used when present
    DeepOnly, // in deep G-buffers only
    WhenUsed  // written only when a material of the scene uses it; used when present
};

// What a scene's materials use, which decides the WhenUsed channels written (bits).
enum ChannelUse : unsigned {
    kUsesOcclusion = 1u,     // an occlusion texture
    kUsesSpecular = 2u,      // KHR_materials_ior, _specular or _unlit
    kUsesClearcoat = 4u,     // KHR_materials_clearcoat
    kUsesSmoothNormals = 8u, // a triangle whose vertex normals differ (Plift)
    kUsesSheen = 16u,        // KHR_materials_sheen
    kUsesPixelSamples = 32u, // deep: several primary rays in some pixel (sample.id, .weight)
    kUsesTransmission = 64u, // KHR_materials_transmission
    kUsesVolume = 128u,      // KHR_materials_volume with an attenuation
    kAllUses = 255u
};

// One entry of the contract: a scalar, a 3-vector or a Cryptomatte layer, in the order
// dhdr-gbuffer writes them.
// The writers (flat and deep), findLayout, the type checks of findGBufferPart and the table of
// docs/gbuffer.md (checked by a test) all follow this table.
struct ContractChannel {
    const char* names[4];
    int components;
    FileType type;
    Need need;
    int Layout::*field; // where findLayout records the index of its first component
    const char* meaning;
    unsigned use = 0; // WhenUsed: the ChannelUse bit that has it written
};

inline constexpr ContractChannel kContract[] = {
    {{kCoverage},
     1,
     FileType::Half,
     Need::Required,
     &Layout::coverage,
     "coverage: 1 where the primary ray hit a surface; a deep sample's alpha"},
    {{kDepth},
     1,
     FileType::Float,
     Need::Required,
     &Layout::depth,
     "camera-space planar depth along the view axis, in scene units (metres for glTF)"},
    {{kDepthBack},
     1,
     FileType::Float,
     Need::DeepOnly,
     &Layout::depthBack,
     "deep samples: the back of the sample, equal to Z (a point on a surface)"},
    {{kPosition[0], kPosition[1], kPosition[2]},
     3,
     FileType::Float,
     Need::Required,
     &Layout::position,
     "world-space hit position"},
    {{kNormal[0], kNormal[1], kNormal[2]},
     3,
     FileType::Half,
     Need::Required,
     &Layout::normal,
     "world-space shading normal, unit length, flipped to face the camera"},
    {{kGeometricNormal[0], kGeometricNormal[1], kGeometricNormal[2]},
     3,
     FileType::Float,
     Need::Optional,
     &Layout::geometricNormal,
     "world-space normal of the surface's triangle, unit length, facing the camera: the side "
     "secondary rays leave from"},
    {{kPositionError},
     1,
     FileType::Float,
     Need::Optional,
     &Layout::positionError,
     "bound on the absolute error of each coordinate of P, scene units: how far secondary rays "
     "start off the surface"},
    {{kLift[0], kLift[1], kLift[2]},
     3,
     FileType::Half,
     Need::WhenUsed,
     &Layout::lift,
     "world-space offset from P to the smooth surface its triangle's vertex normals describe "
     "(Hanika 2021), never below the triangle: where shadow rays near the terminator start",
     kUsesSmoothNormals},
    {{kAlbedo[0], kAlbedo[1], kAlbedo[2]},
     3,
     FileType::Half,
     Need::Required,
     &Layout::albedo,
     "linear base colour: material factor × base-colour texture × vertex colour"},
    {{kRoughness},
     1,
     FileType::Half,
     Need::Required,
     &Layout::roughness,
     "glTF roughness: roughnessFactor × metallic-roughness texture's G"},
    {{kMetallic},
     1,
     FileType::Half,
     Need::Required,
     &Layout::metallic,
     "glTF metallic: metallicFactor × metallic-roughness texture's B"},
    {{kOcclusion},
     1,
     FileType::Half,
     Need::WhenUsed,
     &Layout::occlusion,
     "glTF occlusion: 1 + strength · (occlusion texture's R − 1); scales ambient, environment "
     "and indirect light, never direct light",
     kUsesOcclusion},
    {{kSpecular[0], kSpecular[1], kSpecular[2]},
     3,
     FileType::Half,
     Need::WhenUsed,
     &Layout::specular,
     "the dielectric layer's reflectance at normal incidence: min(((ior − 1)/(ior + 1))² × "
     "specularColorFactor × specularColorTexture's RGB, 1) × specularFactor × specularTexture's "
     "A (KHR_materials_ior, _specular; pbrSpecularGlossiness: its specular); 0.04 without them",
     kUsesSpecular},
    {{kSpecularWeight},
     1,
     FileType::Half,
     Need::WhenUsed,
     &Layout::specularWeight,
     "the dielectric layer's reflectance at grazing incidence: specularFactor × "
     "specularTexture's A; 1 without it",
     kUsesSpecular},
    {{kClearcoat},
     1,
     FileType::Half,
     Need::WhenUsed,
     &Layout::clearcoat,
     "KHR_materials_clearcoat's layer weight: clearcoatFactor × clearcoatTexture's R; 0: no coat",
     kUsesClearcoat},
    {{kClearcoatRoughness},
     1,
     FileType::Half,
     Need::WhenUsed,
     &Layout::clearcoatRoughness,
     "the coat's roughness: clearcoatRoughnessFactor × clearcoatRoughnessTexture's G",
     kUsesClearcoat},
    {{kClearcoatNormal[0], kClearcoatNormal[1], kClearcoatNormal[2]},
     3,
     FileType::Half,
     Need::WhenUsed,
     &Layout::clearcoatNormal,
     "world-space normal of the coat, unit length, facing the camera: clearcoatNormalTexture's, "
     "else the interpolated normal (the base's normal map does not bend the coat)",
     kUsesClearcoat},
    {{kSheen[0], kSheen[1], kSheen[2]},
     3,
     FileType::Half,
     Need::WhenUsed,
     &Layout::sheen,
     "KHR_materials_sheen's colour, linear: sheenColorFactor × sheenColorTexture's RGB; 0: no "
     "sheen",
     kUsesSheen},
    {{kSheenRoughness},
     1,
     FileType::Half,
     Need::WhenUsed,
     &Layout::sheenRoughness,
     "the sheen's roughness: sheenRoughnessFactor × sheenRoughnessTexture's A",
     kUsesSheen},
    {{kTransmission},
     1,
     FileType::Half,
     Need::WhenUsed,
     &Layout::transmission,
     "KHR_materials_transmission's share of the dielectric's base that passes through, thin "
     "walled: transmissionFactor × transmissionTexture's R; 0: opaque",
     kUsesTransmission},
    {{kAttenuation[0], kAttenuation[1], kAttenuation[2]},
     3,
     FileType::Half,
     Need::WhenUsed,
     &Layout::attenuation,
     "KHR_materials_volume: the share of light the medium behind a surface entering it lets "
     "through to the ray's next surface, attenuationColor^(d / attenuationDistance), d the "
     "distance between them; 1 elsewhere",
     kUsesVolume},
    {{kEmission[0], kEmission[1], kEmission[2]},
     3,
     FileType::Half,
     Need::Optional,
     &Layout::emission,
     "linear emitted radiance: emissive factor × strength × emissive texture"},
    {{kObjectId},
     1,
     FileType::Uint,
     Need::Optional,
     &Layout::objectId,
     "index into dhdr:objectNames: the integer itself (1, 2, …)"},
    {{kMaterialId},
     1,
     FileType::Uint,
     Need::Optional,
     &Layout::materialId,
     "index into dhdr:materialNames: the integer itself (1, 2, …)"},
    {{kCryptoObject[0], kCryptoObject[1], kCryptoObject[2], kCryptoObject[3]},
     4,
     FileType::Float,
     Need::Optional,
     &Layout::cryptoObject,
     "Cryptomatte of the objects: rank 0 id and coverage, rank 1 id and coverage"},
    {{kCryptoMaterial[0], kCryptoMaterial[1], kCryptoMaterial[2], kCryptoMaterial[3]},
     4,
     FileType::Float,
     Need::Optional,
     &Layout::cryptoMaterial,
     "Cryptomatte of the materials: rank 0 id and coverage, rank 1 id and coverage"},
    {{kSampleId},
     1,
     FileType::Uint,
     Need::DeepOnly,
     &Layout::sampleId,
     "deep samples of a pixel of several primary rays: which ray (0, 1, …); the samples of one "
     "ray composite over each other front to back, those of different rays are side by side",
     kUsesPixelSamples},
    {{kSampleWeight},
     1,
     FileType::Float,
     Need::DeepOnly,
     &Layout::sampleWeight,
     "deep samples of a pixel of several primary rays: the ray's share of the pixel (1 / the "
     "pixel's rays, whose positions follow the pixel filter); a ray's samples share it",
     kUsesPixelSamples},
};

// A name's Cryptomatte id: MurmurHash3_x86_32 (seed 0) of its UTF-8 bytes, as the float with
// those bits, bit 23 flipped when the exponent would be 0 or 255 (no denormals, infinities or
// NaNs); `hash` receives the hash itself (for the manifest).
float cryptomatteId(const std::string& name, std::uint32_t* hash = nullptr);
// The Cryptomatte header of a layer (`cryptomatte/<key>/name`, `hash`, `conversion`,
// `manifest`: a JSON object of name → 8 hex digits), key = the first 7 hex digits of the
// layer name's hash.
void writeCryptomatteHeader(OIIO::ImageSpec& spec, const std::string& layer,
                            const std::vector<std::string>& names);

// All channels of the flat contract in writing order (kContract without the deep-only ones),
// with the WhenUsed ones that `uses` (ChannelUse bits) asks for.
std::vector<std::string> channelNames(unsigned uses = 0);
// A deep G-buffer sample's channels: all of kContract, in its order, the same WhenUsed ones.
std::vector<std::string> deepChannelNames(unsigned uses = 0);
// The file types of `names`: the contract's for its channels, float for any other (the
// motion layer).
std::vector<OIIO::TypeDesc> channelFormats(const std::vector<std::string>& names);
// Whether `names` are, in order, the channels dhdr-gbuffer writes: the flat (or `deep`)
// contract's, with or without the WhenUsed ones, then the motion layer or not.
bool isWrittenLayout(const std::vector<std::string>& names, bool deep);

// Finds the channels that dhdr-light shades with (A, Z, P, N, albedo, roughness, metallic;
// emission and ids are optional). On a missing channel returns false and names it in
// `missing`.
bool findLayout(const OIIO::ImageSpec& spec, Layout& layout, std::string& missing);

// The part (subimage) of the file at `path` that holds a G-buffer: the first whose channels
// findLayout finds, stored in the contract's types (a normal stored as uint would clamp).
// −1 with `error` saying why when none does; `error` names the file's problem, not the file.
int findGBufferPart(const std::string& path, std::string& error);

// What dhdr-light (and the Python module) check of a G-buffer file before reading a pixel: it
// exists, a part holds a G-buffer (findGBufferPart: `part`), whether that part is deep, and
// that it is within the pixel limit. False with `error` naming the file.
bool probeGBufferFile(const std::string& path, int& part, bool& deep, std::string& error);

// What the header says of the camera that rendered the buffer.
struct CameraInfo {
    glm::dmat4 worldToCamera{1.0};
    glm::dmat4 worldToNDC{1.0};
    glm::dvec3 position{0.0};
    // An orthographic projection (the last row of cameraToNDC is 0 0 0 1): every view ray
    // runs along `forward`, the camera's −Z in world space.
    bool orthographic = false;
    glm::dvec3 forward{0.0, 0.0, -1.0};

    // The unit vector from a world-space point towards the eye that sees it.
    glm::dvec3 toEye(const glm::dvec3& p) const {
        return orthographic ? -forward : glm::normalize(position - p);
    }
};

// Reads worldToCamera and worldToNDC (OpenEXR's standard attributes) from `spec`; the
// position, direction and kind of projection follow from them. False, saying why in `error`,
// when either is missing, not finite or not invertible.
bool readCamera(const OIIO::ImageSpec& spec, CameraInfo& camera, std::string& error);
void writeCamera(OIIO::ImageSpec& spec, const CameraInfo& camera);

} // namespace dhdr::gbuffer
