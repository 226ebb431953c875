#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer_import.h>
#include <dhdr/io/motion_channels.h>
#include <fstream>
#include <nlohmann/json.hpp>

namespace dhdr {

ChannelMap blenderChannelMap() {
    ChannelMap m;
    m.name = "blender";
    const std::string v = "ViewLayer.";
    m.depth.channels = {v + "Depth.Z"};
    m.depth.required = true;
    m.position.channels = {v + "Position.X", v + "Position.Y", v + "Position.Z"};
    m.position.zUp = true;
    m.position.required = true;
    m.normal.channels = {v + "Normal.X", v + "Normal.Y", v + "Normal.Z"};
    m.normal.zUp = true;
    m.normal.required = true;
    m.albedo.channels = {v + "BaseColor.R", v + "BaseColor.G", v + "BaseColor.B"};
    m.albedo.fallback = {v + "DiffCol.R", v + "DiffCol.G", v + "DiffCol.B"};
    m.albedo.value = 0.8f;
    m.roughness.channels = {v + "Roughness.X"};
    m.roughness.value = 0.5f;
    m.metallic.channels = {v + "Metallic.X"};
    m.metallic.value = 0.0f;
    m.emission.channels = {v + "Emit.R", v + "Emit.G", v + "Emit.B"};
    // Blender's Vector pass is in the motion layer's convention: found as dhdr-motionblur finds
    // it, under whatever view layer it is.
    m.motionByName = true;
    return m;
}

bool readChannelMap(const std::string& path, ChannelMap& map, std::string& error) {
    std::ifstream in(path);
    if (!in) {
        error = "cannot open the channel map";
        return false;
    }
    try {
        const nlohmann::json doc = nlohmann::json::parse(in);
        if (!doc.is_object()) throw std::runtime_error("the top level is not an object");
        map = ChannelMap{};
        map.name = path;
        const std::pair<const char*, ChannelSource*> fields[] = {
            {"depth", &map.depth},       {"position", &map.position},   {"normal", &map.normal},
            {"albedo", &map.albedo},     {"roughness", &map.roughness}, {"metallic", &map.metallic},
            {"emission", &map.emission}, {"coverage", &map.coverage},   {"motion", &map.motion}};
        for (const auto& [key, source] : fields) {
            if (!doc.contains(key)) continue;
            const nlohmann::json& f = doc.at(key);
            if (!f.is_object()) throw std::runtime_error(std::string(key) + " is not an object");
            for (const auto& [k, v] : f.items())
                if (k != "channels" && k != "fallback" && k != "scale" && k != "axes" &&
                    k != "value" && k != "required")
                    throw std::runtime_error(std::string(key) + ": unknown key '" + k + "'");
            if (f.contains("channels"))
                source->channels = f.at("channels").get<std::vector<std::string>>();
            if (f.contains("fallback"))
                source->fallback = f.at("fallback").get<std::vector<std::string>>();
            source->scale = f.value("scale", 1.0f);
            source->value = f.value("value", 0.0f);
            source->required = f.value("required", false);
            const std::string axes = f.value("axes", std::string("y-up"));
            if (axes != "y-up" && axes != "z-up")
                throw std::runtime_error(std::string(key) + ": axes must be y-up or z-up");
            source->zUp = axes == "z-up";
            const bool motion = std::string(key) == "motion";
            if (motion && (f.contains("axes") || f.contains("fallback") || f.contains("value")))
                throw std::runtime_error("motion: only channels, scale and required apply (screen "
                                         "vectors have no axes, and no constant stands for them)");
            const size_t n = motion ? 4
                             : std::string(key) == "position" || std::string(key) == "normal" ||
                                     std::string(key) == "albedo" || std::string(key) == "emission"
                                 ? 3
                                 : 1;
            for (const auto* list : {&source->channels, &source->fallback})
                if (!list->empty() && list->size() != n)
                    throw std::runtime_error(std::string(key) + ": needs " + std::to_string(n) +
                                             " channel names");
            if (!std::isfinite(source->scale) || !std::isfinite(source->value))
                throw std::runtime_error(std::string(key) + ": scale and value must be finite");
        }
        // What every map must say, checked here so that the error names the map, not the
        // passes it is applied to.
        for (const auto& [key, source] :
             {std::pair<const char*, ChannelSource*>{"depth", &map.depth},
              {"position", &map.position},
              {"normal", &map.normal}})
            if (source->channels.empty() && source->fallback.empty())
                throw std::runtime_error(std::string(key) +
                                         " needs channels (a map needs depth, position and "
                                         "normal)");
        map.backgroundDepth = doc.value("backgroundDepth", 1e9f);
        if (!(map.backgroundDepth > 0.0f))
            throw std::runtime_error("backgroundDepth must be positive");
        for (const auto& item : doc.items()) {
            // A named key, not a structured binding: clang 14 (the fuzz build) cannot capture
            // a binding in a lambda.
            const std::string& k = item.key();
            if (k != "backgroundDepth" && k != "$comment" &&
                std::none_of(std::begin(fields), std::end(fields),
                             [&](const auto& f) { return k == f.first; }))
                throw std::runtime_error("unknown key '" + k + "'");
        }
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
    return true;
}

namespace {

// Whether `src` is what a channel map reads: flat float passes in memory.
bool importable(const OIIO::ImageBuf& src, std::string& error) {
    const OIIO::ImageSpec& in = src.spec();
    if (in.deep || src.deep()) {
        error = "a deep image: a channel map reads flat passes (a deep dhdr G-buffer is read as "
                "it is, without --channels)";
        return false;
    }
    if (in.format != OIIO::TypeDesc::FLOAT || !src.localpixels()) {
        error = "the passes must be read as float pixels in memory";
        return false;
    }
    return true;
}

// The source channels of each quantity (empty: none, a constant stands for it).
struct SourceChannels {
    std::vector<int> depth, position, normal, albedo, roughness, metallic, emission, coverage;
    std::vector<int> motion; // four, or none
};

// The source channels of a quantity: its own, its fallback, or none (a constant); false with
// `error` where it has none and is required or `needed`.
bool pickChannels(const OIIO::ImageSpec& in, const ChannelMap& map, const char* what,
                  const ChannelSource& s, std::vector<int>& index, bool needed,
                  std::vector<std::string>& warnings, std::string& error) {
    index.clear();
    for (const auto* list : {&s.channels, &s.fallback}) {
        index.clear();
        for (const std::string& name : *list)
            index.push_back(in.channelindex(name));
        if (!list->empty() &&
            std::all_of(index.begin(), index.end(), [](int c) { return c >= 0; })) {
            if (list == &s.fallback)
                warnings.push_back(std::string(what) + ": no " + s.channels.front() + ", using " +
                                   s.fallback.front() + " instead");
            return true;
        }
    }
    index.clear();
    if (s.required || needed) {
        error = std::string("no channel '") +
                (s.channels.empty() ? std::string(what) : s.channels.front()) + "' for the " +
                what + " (channel map " + map.name + ")";
        return false;
    }
    if (!s.channels.empty())
        warnings.push_back(std::string(what) + ": no " + s.channels.front() + ", using " +
                           std::to_string(s.value));
    return true;
}

// Motion: the channels the map names (all four, or none with a warning), or those found by
// name; no constant stands in for them.
bool pickMotion(const OIIO::ImageSpec& in, const ChannelMap& map, std::vector<int>& motion,
                std::vector<std::string>& warnings, std::string& error) {
    if (!map.motion.channels.empty()) {
        for (const std::string& name : map.motion.channels)
            motion.push_back(in.channelindex(name));
        if (std::any_of(motion.begin(), motion.end(), [](int c) { return c < 0; })) {
            motion.clear();
            if (map.motion.required) {
                error = "no channel '" + map.motion.channels.front() +
                        "' for the motion (channel map " + map.name + ")";
                return false;
            }
            warnings.push_back("motion: no " + map.motion.channels.front() + ", no motion layer");
        }
    } else if (map.motionByName) {
        if (const int first = findMotionChannels(in).motion; first >= 0)
            motion = {first, first + 1, first + 2, first + 3};
    }
    return true;
}

// Every quantity's source channels; depth, position and normal are needed whatever the map
// says of them.
bool pickAllChannels(const OIIO::ImageSpec& in, const ChannelMap& map, SourceChannels& c,
                     std::vector<std::string>& warnings, std::string& error) {
    auto pick = [&](const char* what, const ChannelSource& s, std::vector<int>& index,
                    bool needed = false) {
        return pickChannels(in, map, what, s, index, needed, warnings, error);
    };
    return pick("depth", map.depth, c.depth, true) &&
           pick("position", map.position, c.position, true) &&
           pick("normal", map.normal, c.normal, true) && pick("albedo", map.albedo, c.albedo) &&
           pick("roughness", map.roughness, c.roughness) &&
           pick("metallic", map.metallic, c.metallic) &&
           pick("emission", map.emission, c.emission) &&
           pick("coverage", map.coverage, c.coverage) &&
           pickMotion(in, map, c.motion, warnings, error);
}

// The G-buffer's spec over `in`'s window: its channels, with the motion layer's where there
// is motion.
OIIO::ImageSpec importedSpec(const OIIO::ImageSpec& in, bool withMotion) {
    std::vector<std::string> names = gbuffer::channelNames();
    if (withMotion)
        names.insert(names.end(), std::begin(gbuffer::kMotion), std::end(gbuffer::kMotion));
    OIIO::ImageSpec spec = in;
    spec.nchannels = int(names.size());
    spec.channelnames = names;
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.channelformats.clear();
    spec.alpha_channel = 0;
    spec.z_channel = 1;
    return spec;
}

// Channel k of a quantity in source pixel p, scaled, or its constant.
float sourceValue(const float* p, const std::vector<int>& idx, const ChannelSource& s, int k) {
    return idx.empty() ? s.value : p[idx[size_t(k)]] * s.scale;
}

// A vector quantity in source pixel p, turned Y-up.
glm::vec3 sourceVector(const float* p, const std::vector<int>& idx, const ChannelSource& s) {
    glm::vec3 v(sourceValue(p, idx, s, 0), sourceValue(p, idx, s, idx.empty() ? 0 : 1),
                sourceValue(p, idx, s, idx.empty() ? 0 : 2));
    // Z-up to Y-up: (x, y, z) → (x, z, −y).
    return s.zUp ? glm::vec3(v.x, v.z, -v.y) : v;
}

// Where the G-buffer's channels are, and the motion layer's first and its scale.
struct ImportLayout {
    gbuffer::Layout L;
    int nchannels;
    size_t motionAt;
    float motionScale;
};

// One G-buffer pixel `o` from source pixel `p`.
void importPixel(const float* p, float* o, const ChannelMap& map, const SourceChannels& c,
                 const ImportLayout& out) {
    const gbuffer::Layout& L = out.L;
    const float z = sourceValue(p, c.depth, map.depth, 0);
    const bool background =
        !std::isfinite(z) || z >= map.backgroundDepth ||
        (!c.coverage.empty() && !(sourceValue(p, c.coverage, map.coverage, 0) > 0.0f));
    std::fill(o, o + out.nchannels, 0.0f);
    // Motion as it is, background too (Blender's vectors of the world behind).
    for (size_t k = 0; k < c.motion.size(); ++k)
        o[out.motionAt + k] = p[c.motion[k]] * out.motionScale;
    if (background) {
        o[L.depth] = INFINITY;
        return;
    }
    o[L.coverage] =
        c.coverage.empty() ? 1.0f : std::min(sourceValue(p, c.coverage, map.coverage, 0), 1.0f);
    o[L.depth] = z;
    const glm::vec3 P = sourceVector(p, c.position, map.position);
    const glm::vec3 N = sourceVector(p, c.normal, map.normal);
    const glm::vec3 A = sourceVector(p, c.albedo, map.albedo);
    const glm::vec3 E = sourceVector(p, c.emission, map.emission);
    for (int k = 0; k < 3; ++k) {
        o[L.position + k] = P[k];
        o[L.normal + k] = N[k];
        o[L.albedo + k] = A[k];
        o[L.emission + k] = E[k];
    }
    o[L.roughness] = sourceValue(p, c.roughness, map.roughness, 0);
    o[L.metallic] = sourceValue(p, c.metallic, map.metallic, 0);
}

} // namespace

bool importGBuffer(const OIIO::ImageBuf& src, const ChannelMap& map, OIIO::ImageBuf& dst,
                   std::vector<std::string>& warnings, std::string& error) {
    if (!importable(src, error)) return false;
    const OIIO::ImageSpec& in = src.spec();
    SourceChannels c;
    if (!pickAllChannels(in, map, c, warnings, error)) return false;
    const OIIO::ImageSpec spec = importedSpec(in, !c.motion.empty());
    dst.reset(spec);
    ImportLayout out;
    OIIO::ImageSpec layoutSpec(1, 1, spec.nchannels, OIIO::TypeDesc::FLOAT);
    layoutSpec.channelnames = spec.channelnames;
    std::string missing;
    gbuffer::findLayout(layoutSpec, out.L, missing);
    out.nchannels = spec.nchannels;
    out.motionAt = gbuffer::channelNames().size();
    out.motionScale = map.motion.channels.empty() ? 1.0f : map.motion.scale;
    const float* pixels = static_cast<const float*>(src.localpixels());
    const size_t nch = size_t(in.nchannels);
    OIIO::ImageBufAlgo::parallel_image(src.roi(), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            for (int x = r.xbegin; x < r.xend; ++x)
                importPixel(pixels + (size_t(y - in.y) * size_t(in.width) + size_t(x - in.x)) * nch,
                            static_cast<float*>(dst.pixeladdr(x, y)), map, c, out);
    });
    return true;
}

} // namespace dhdr
