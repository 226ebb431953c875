#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/deferred/lights/light.h>
#include <dhdr/deferred/scene/lights.h>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

namespace dhdr {

using nlohmann::json;

namespace {

// A finite number that a float holds: 1e39 is a double but would be +Inf in the lighting, and
// 1e-50 would be 0 (a range, a radius: refused as zero with a misleading message, or a colour
// silently black). A number is 0 or one whose float is not 0 (the smallest, 1.4e-45, written
// by --lights-out included).
bool isFloat(const json& v) {
    if (!v.is_number()) return false;
    const double d = v.get<double>();
    return std::isfinite(d) && std::abs(d) <= double(std::numeric_limits<float>::max()) &&
           (d == 0.0 || float(d) != 0.0f);
}

// Thrown inside the parser only; becomes the `error` string.
struct LightError {
    std::string message;
};

class LightReader {
public:
    LightReader(const json& j, size_t index) : m_j(j), m_index(index) {}

    [[noreturn]] void fail(const std::string& field, const std::string& what) const {
        throw LightError{"light " + std::to_string(m_index) + ": \"" + field + "\" " + what};
    }

    bool has(const char* field) const { return m_j.contains(field); }

    float number(const char* field, float fallback, bool required = false) const {
        if (!m_j.contains(field)) {
            if (required) fail(field, "is required");
            return fallback;
        }
        const json& v = m_j.at(field);
        if (!isFloat(v))
            fail(field, "must be a number that a float holds (0, or 1.4e-45 to 3.4e38 in "
                        "magnitude)");
        return v.get<float>();
    }

    glm::vec3 vector3(const char* field, glm::vec3 fallback, bool required = false) const {
        if (!m_j.contains(field)) {
            if (required) fail(field, "is required");
            return fallback;
        }
        const json& v = m_j.at(field);
        if (!v.is_array() || v.size() != 3) fail(field, "must be an array of 3 numbers");
        glm::vec3 out;
        for (int i = 0; i < 3; ++i) {
            if (!isFloat(v[size_t(i)]))
                fail(field, "must be an array of 3 numbers that a float holds (0, or 1.4e-45 "
                            "to 3.4e38 in magnitude)");
            out[i] = v[size_t(i)].get<float>();
        }
        return out;
    }

private:
    const json& m_j;
    size_t m_index;
};

// The keys of a light in a lights file, and the types each belongs to (docs/lights.md's
// table). Any other key is an error, as in the channel map: a misspelt "colour" or "rnage"
// would otherwise be dropped and the light silently wrong.
struct LightField {
    const char* key;
    std::vector<LightType> types; // empty: every type
};

const std::vector<LightField>& lightFields() {
    using T = LightType;
    static const std::vector<LightField> fields = {
        {"type", {}},
        {"name", {}},
        {"color", {}},
        {"intensity", {}},
        {"$comment", {}},
        {"position", {T::Point, T::Spot, T::Sphere, T::Rectangle}},
        {"range", {T::Point, T::Spot, T::Sphere, T::Rectangle}},
        {"direction", {T::Spot, T::Directional, T::Rectangle}},
        {"innerConeAngle", {T::Spot}},
        {"outerConeAngle", {T::Spot}},
        {"radius", {T::Sphere}},
        {"angle", {T::Directional}},
        {"width", {T::Rectangle}},
        {"height", {T::Rectangle}},
        {"up", {T::Rectangle}},
        {"image", {T::Environment}},
        {"rotation", {T::Environment}},
        {"sun", {T::Environment}},
    };
    return fields;
}

// Edit distance with transpositions (optimal string alignment), case-insensitive, for "did
// you mean" on a misspelt key: "rnage" is one edit from "range".
size_t editDistance(const std::string& a, const std::string& b) {
    const size_t n = a.size(), m = b.size();
    std::vector<std::vector<size_t>> d(n + 1, std::vector<size_t>(m + 1));
    auto same = [&](size_t i, size_t j) {
        return std::tolower((unsigned char)a[i]) == std::tolower((unsigned char)b[j]);
    };
    for (size_t i = 0; i <= n; ++i)
        for (size_t j = 0; j <= m; ++j) {
            if (i == 0 || j == 0) {
                d[i][j] = i + j;
                continue;
            }
            d[i][j] = std::min(
                {d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (same(i - 1, j - 1) ? 0 : 1)});
            if (i > 1 && j > 1 && same(i - 1, j - 2) && same(i - 2, j - 1))
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[n][m];
}

// Fails on the first key of `j` that a light of `light.type` does not have, naming the key
// and the light (index, type and name).
void checkKeys(const json& j, const Light& light, size_t index) {
    for (const auto& item : j.items()) {
        const std::string& key = item.key();
        const LightField* field = nullptr;
        for (const LightField& f : lightFields())
            if (key == f.key) field = &f;
        const bool applies =
            field && (field->types.empty() || std::find(field->types.begin(), field->types.end(),
                                                        light.type) != field->types.end());
        if (applies) continue;
        std::string message = "light " + std::to_string(index) + " (" + lightTypeName(light.type) +
                              (light.name.empty() ? "" : " \"" + light.name + "\"") + "): ";
        if (field) {
            std::string owners;
            for (size_t k = 0; k < field->types.size(); ++k)
                owners += std::string(k == 0                         ? ""
                                      : k + 1 == field->types.size() ? " or "
                                                                     : ", ") +
                          lightTypeName(field->types[k]);
            message += "\"" + key + "\" does not apply to a " + lightTypeName(light.type) +
                       " light (only to " + owners + ")";
        } else {
            message += "unknown key \"" + key + "\"";
            // The closest key this type has, when it is a likely misspelling.
            const LightField* closest = nullptr;
            size_t best = 3;
            for (const LightField& f : lightFields()) {
                const bool ofType = f.types.empty() || std::find(f.types.begin(), f.types.end(),
                                                                 light.type) != f.types.end();
                const size_t d = editDistance(key, f.key);
                if (ofType && f.key[0] != '$' && d < best) {
                    best = d;
                    closest = &f;
                }
            }
            if (closest) message += std::string(" (did you mean \"") + closest->key + "\"?)";
        }
        throw LightError{message};
    }
}

// The light's type, named by "type".
LightType readType(const json& j, const LightReader& r) {
    if (!j.contains("type") || !j.at("type").is_string()) r.fail("type", "is required");
    const std::string type = j.at("type").get<std::string>();
    if (type == "point") return LightType::Point;
    if (type == "spot") return LightType::Spot;
    if (type == "directional") return LightType::Directional;
    if (type == "ambient") return LightType::Ambient;
    if (type == "sphere") return LightType::Sphere;
    if (type == "rectangle") return LightType::Rectangle;
    if (type == "environment") return LightType::Environment;
    r.fail("type", "must be point, spot, directional, ambient, sphere, rectangle or "
                   "environment, not \"" +
                       type + "\"");
}

// Every light's colour and intensity.
void readEmission(const LightReader& r, Light& light) {
    light.color = r.vector3("color", glm::vec3(1.0f));
    if (light.color.r < 0 || light.color.g < 0 || light.color.b < 0)
        r.fail("color", "must not be negative");
    light.intensity = r.number("intensity", 1.0f);
    if (light.intensity < 0) r.fail("intensity", "must not be negative");
}

// An environment's image, its rotation and its sun.
void readEnvironment(const json& j, const LightReader& r, Light& light) {
    if (!j.contains("image") || !j.at("image").is_string() ||
        j.at("image").get<std::string>().empty())
        r.fail("image", "is required: the path of an equirectangular HDR image");
    light.image = j.at("image").get<std::string>();
    light.rotation = r.number("rotation", 0.0f) * 3.14159265358979f / 180.0f;
    if (!r.has("sun")) return;
    const nlohmann::json& sun = j.at("sun");
    if (sun.is_string() && sun.get<std::string>() == "off") {
        light.sunThreshold = 0.0f;
    } else {
        light.sunThreshold = r.number("sun", 0.0f);
        if (!(light.sunThreshold > 0.0f))
            r.fail("sun", "must be \"off\" or a positive luminance threshold");
    }
}

// A local light's position and range.
void readPlacement(const LightReader& r, Light& light) {
    light.position = r.vector3("position", glm::vec3(0.0f), true);
    if (r.has("range")) {
        light.range = r.number("range", 0.0f);
        if (!(light.range > 0)) r.fail("range", "must be a positive number");
    }
}

// The direction of a spot, directional or rectangle light.
void readDirection(const LightReader& r, Light& light) {
    const glm::vec3 d = r.vector3("direction", glm::vec3(0.0f, 0.0f, -1.0f), true);
    if (glm::length(d) == 0.0f) r.fail("direction", "must not be zero");
    light.direction = glm::normalize(d);
}

// A directional light's angular diameter.
void readDirectional(const LightReader& r, Light& light) {
    if (!r.has("angle")) return;
    const float degrees = r.number("angle", 0.0f);
    if (!(degrees >= 0.0f && degrees < 180.0f)) r.fail("angle", "must be in [0, 180) degrees");
    light.angle = degrees * 3.14159265358979f / 180.0f;
}

void readSphere(const LightReader& r, Light& light) {
    light.radius = r.number("radius", 0.0f, true);
    if (!(light.radius > 0)) r.fail("radius", "must be a positive number");
    if (light.range <= light.radius) r.fail("range", "must exceed the radius");
}

void readRectangle(const LightReader& r, Light& light) {
    light.width = r.number("width", 0.0f, true);
    light.height = r.number("height", 0.0f, true);
    if (!(light.width > 0)) r.fail("width", "must be a positive number");
    if (!(light.height > 0)) r.fail("height", "must be a positive number");
    // `up` need only not be parallel to the normal; it is made perpendicular to it.
    const glm::vec3 up = r.vector3("up", glm::vec3(0.0f, 1.0f, 0.0f));
    const glm::vec3 ortho = up - glm::dot(up, light.direction) * light.direction;
    if (glm::length(ortho) < 1e-4f * std::max(glm::length(up), 1e-30f))
        r.fail("up", "must not be parallel to \"direction\"");
    light.up = glm::normalize(ortho);
    const float halfDiagonal =
        0.5f * std::sqrt(light.width * light.width + light.height * light.height);
    if (light.range <= halfDiagonal) r.fail("range", "must exceed half the diagonal");
}

void readSpot(const LightReader& r, Light& light) {
    light.innerConeAngle = r.number("innerConeAngle", 0.0f);
    light.outerConeAngle = r.number("outerConeAngle", 0.7853982f);
    if (!(light.outerConeAngle > 0 && light.outerConeAngle <= 1.5707964f))
        r.fail("outerConeAngle", "must be in (0, π/2]");
    if (!(light.innerConeAngle >= 0 && light.innerConeAngle < light.outerConeAngle))
        r.fail("innerConeAngle", "must be in [0, outerConeAngle)");
}

Light parseLight(const json& j, size_t index) {
    LightReader r(j, index);
    if (!j.is_object()) throw LightError{"light " + std::to_string(index) + ": not an object"};
    Light light;
    light.type = readType(j, r);
    if (j.contains("name")) {
        if (!j.at("name").is_string()) r.fail("name", "must be a string");
        light.name = j.at("name").get<std::string>();
    }
    checkKeys(j, light, index);
    readEmission(r, light);
    // The fields of each family the light belongs to, in this order (the first error wins).
    const LightType t = light.type;
    if (t == LightType::Environment) readEnvironment(j, r, light);
    if (light.isLocal()) readPlacement(r, light);
    if (t == LightType::Spot || t == LightType::Directional || t == LightType::Rectangle)
        readDirection(r, light);
    if (t == LightType::Directional) readDirectional(r, light);
    if (t == LightType::Sphere) readSphere(r, light);
    if (t == LightType::Rectangle) readRectangle(r, light);
    if (t == LightType::Spot) readSpot(r, light);
    return light;
}

} // namespace

const char* lightTypeName(LightType t) {
    switch (t) {
    case LightType::Point:
        return "point";
    case LightType::Spot:
        return "spot";
    case LightType::Directional:
        return "directional";
    case LightType::Ambient:
        return "ambient";
    case LightType::Sphere:
        return "sphere";
    case LightType::Rectangle:
        return "rectangle";
    case LightType::Mesh:
        return "emissive mesh";
    case LightType::Environment:
        return "environment";
    }
    return "point";
}

bool parseLights(const std::string& text, std::vector<Light>& lights, std::string& error) {
    lights.clear();
    // Each light is converted as soon as the parser has read it, and dropped from the
    // document, so that a file of 100,000 lights never exists as a whole JSON tree.
    enum class Root { Unknown, Object, Array } root = Root::Unknown;
    std::string key; // the current key of the root object
    bool sawLights = false;
    const json::parser_callback_t collect = [&](int depth, json::parse_event_t event,
                                                json& parsed) {
        if (depth == 0 && event == json::parse_event_t::object_start) root = Root::Object;
        if (depth == 0 && event == json::parse_event_t::array_start) root = Root::Array;
        if (depth == 1 && event == json::parse_event_t::key && root == Root::Object) {
            key = parsed.get<std::string>();
            sawLights = sawLights || key == "lights";
            if (key != "lights" && key != "$schema" && key != "$comment")
                throw LightError{"unknown key \"" + key + "\" at the top level" +
                                 (editDistance(key, "lights") < 3
                                      ? " (did you mean \"lights\"?)"
                                      : " (a lights file has \"lights\")")};
        }
        const bool lightDepth = (root == Root::Object && depth == 2 && key == "lights") ||
                                (root == Root::Array && depth == 1);
        if (lightDepth && event == json::parse_event_t::object_end) {
            lights.push_back(parseLight(parsed, lights.size()));
            return false;
        }
        if (lightDepth &&
            (event == json::parse_event_t::value || event == json::parse_event_t::array_end))
            throw LightError{"light " + std::to_string(lights.size()) + ": not an object"};
        return true;
    };
    json doc;
    try {
        doc = json::parse(text, collect);
    } catch (const json::exception& e) {
        // parse_error, and out_of_range for numbers like 1e400 that no double holds.
        lights.clear();
        error = std::string("not valid JSON: ") + e.what();
        return false;
    } catch (const LightError& e) {
        lights.clear();
        error = e.message;
        return false;
    }
    if (root == Root::Object && !sawLights) {
        error = "no \"lights\" array";
        return false;
    }
    if (root == Root::Object && !doc["lights"].is_array()) {
        lights.clear();
        error = "\"lights\" must be an array";
        return false;
    }
    if (root == Root::Unknown) {
        error = "expected an object with a \"lights\" array, or an array of lights";
        return false;
    }
    return true;
}

bool readLightsFile(const std::string& path, std::vector<Light>& lights, std::string& error,
                    std::vector<std::string>& warnings) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        error = path + ": is a folder, not a lights file";
        return false;
    }
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in || in.tellg() < 0) {
        error = path + ": cannot open the lights file";
        return false;
    }
    // Read straight into one string: a file of 100,000 lights is 13 MB.
    std::string text(size_t(in.tellg()), '\0');
    in.seekg(0);
    if (!in.read(text.data(), std::streamsize(text.size()))) {
        error = path + ": cannot read the lights file";
        return false;
    }
    if (!parseLights(text, lights, error)) {
        error = path + ": " + error;
        return false;
    }
    // Environment images: relative to the lights file's folder.
    if (!loadEnvironmentImages(lights, std::filesystem::path(path).parent_path().string(), error,
                               warnings)) {
        error = path + ": " + error;
        return false;
    }
    return true;
}

bool loadEnvironmentImages(std::vector<Light>& lights, const std::string& folderName,
                           std::string& error, std::vector<std::string>& warnings) {
    // Each image baked once, whichever lights share it.
    const std::filesystem::path folder(folderName);
    std::map<std::string, std::shared_ptr<const Ibl>> baked;
    for (size_t i = 0; i < lights.size(); ++i) {
        Light& light = lights[i];
        if (light.type != LightType::Environment) continue;
        const std::filesystem::path image(light.image);
        light.image = image.is_absolute() ? image.string() : (folder / image).string();
        const std::string key = light.image + "\n" + std::to_string(light.sunThreshold);
        std::shared_ptr<const Ibl>& ibl = baked[key];
        const std::string which = "light " + std::to_string(i) +
                                  (light.name.empty() ? "" : " \"" + light.name + "\"") +
                                  ": environment image " + light.image + ": ";
        if (!ibl) {
            auto loaded = std::make_shared<Ibl>();
            bool bakedHere = false;
            std::string why;
            long long replaced = 0;
            IblBakeParams params;
            if (light.sunThreshold >= 0.0f) params.sunThreshold = light.sunThreshold;
            if (!loadIbl(light.image, params, *loaded, bakedHere, why, &replaced)) {
                error = which + why;
                return false;
            }
            // A bake split its sun (or not) when it was made; a different wish cannot be
            // honoured from its levels.
            if (!bakedHere && light.sunThreshold >= 0.0f &&
                light.sunThreshold != loaded->params.sunThreshold) {
                error = which + "\"sun\" applies to images baked when loaded; " +
                        "this file was baked by dhdr-ibl with its sun " +
                        (loaded->params.sunThreshold > 0.0f
                             ? "split at luminance " + std::to_string(loaded->params.sunThreshold)
                             : std::string("not split")) +
                        ": bake it again with dhdr-ibl --sun-threshold, or drop \"sun\"";
                return false;
            }
            loaded->bakedOnLoading = bakedHere;
            if (replaced > 0)
                warnings.push_back(light.image + ": " + std::to_string(replaced) +
                                   " NaN or infinite texel values replaced by 0");
            ibl = std::move(loaded);
        }
        light.ibl = ibl;
    }
    // Each environment's sun, a directional light after the lights of the file.
    const size_t count = lights.size();
    for (size_t i = 0; i < count; ++i)
        if (lights[i].type == LightType::Environment && lights[i].ibl->sun.found())
            lights.push_back(environmentSunLight(lights[i]));
    return true;
}

Light environmentSunLight(const Light& environment) {
    const EnvironmentSun& sun = environment.ibl->sun;
    const glm::vec3 E = sun.illuminance;
    const float Y = luminance(E);
    Light light;
    light.type = LightType::Directional;
    light.name =
        (environment.name.empty() ? std::string("environment") : environment.name) + " sun";
    light.direction = -fromEnvironment(environment, sun.direction);
    light.color = (Y > 0.0f ? E / Y : glm::vec3(1.0f)) * environment.color;
    light.intensity = Y * environment.intensity;
    light.angle = sun.angle;
    light.environmentSun = true;
    return light;
}

namespace {

// The shortest decimal that reads back as the same float, so that a written file shows 0.85
// rather than the 0.8500000238418579 a double conversion would.
double shortest(float v) {
    for (int digits = 6; digits < 9; ++digits) {
        char text[32];
        std::snprintf(text, sizeof text, "%.*g", digits, double(v));
        const double d = std::strtod(text, nullptr);
        if (float(d) == v) return d;
    }
    return double(v);
}

nlohmann::ordered_json jsonVector(const glm::vec3& v) {
    return {shortest(v.x), shortest(v.y), shortest(v.z)};
}

} // namespace

std::string formatLights(const std::vector<Light>& lights) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const Light& l : lights) {
        // An emissive mesh comes from the scene, which dhdr-light reads itself (--scene); an
        // environment's sun from its image.
        if (l.type == LightType::Mesh || l.environmentSun) continue;
        nlohmann::ordered_json j;
        j["type"] = lightTypeName(l.type);
        if (!l.name.empty()) j["name"] = l.name;
        j["color"] = jsonVector(l.color);
        j["intensity"] = shortest(l.intensity);
        if (l.isLocal()) {
            j["position"] = jsonVector(l.position);
            if (std::isfinite(l.range)) j["range"] = shortest(l.range);
        }
        if (l.type == LightType::Spot || l.type == LightType::Directional ||
            l.type == LightType::Rectangle)
            j["direction"] = jsonVector(l.direction);
        if (l.type == LightType::Spot) {
            j["innerConeAngle"] = shortest(l.innerConeAngle);
            j["outerConeAngle"] = shortest(l.outerConeAngle);
        }
        if (l.type == LightType::Sphere) j["radius"] = shortest(l.radius);
        if (l.type == LightType::Directional && l.angle > 0.0f)
            j["angle"] = shortest(l.angle * 180.0f / 3.14159265f);
        if (l.type == LightType::Environment) {
            j["image"] = l.image;
            j["rotation"] = shortest(l.rotation * 180.0f / 3.14159265f);
            if (l.sunThreshold == 0.0f)
                j["sun"] = "off";
            else if (l.sunThreshold > 0.0f)
                j["sun"] = shortest(l.sunThreshold);
        }
        if (l.type == LightType::Rectangle) {
            j["width"] = shortest(l.width);
            j["height"] = shortest(l.height);
            j["up"] = jsonVector(l.up);
        }
        list.push_back(j);
    }
    nlohmann::ordered_json doc;
    doc["lights"] = list;
    return doc.dump(2) + "\n";
}

} // namespace dhdr
