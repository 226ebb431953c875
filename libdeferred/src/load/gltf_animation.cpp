#include "load/gltf_animation.h"

#include <cmath>
#include <glm/gtc/type_ptr.hpp>

namespace dhdr::detail {

namespace {

using nlohmann::json;

bool numbers(const json& node, const char* key, size_t count, double* out) {
    if (!node.contains(key) || !node[key].is_array() || node[key].size() != count) return false;
    for (size_t i = 0; i < count; ++i) {
        if (!node[key][i].is_number()) return false;
        out[i] = node[key][i].get<double>();
    }
    return true;
}

// The number of morph targets of node n's mesh (its first primitive's), 0 when none.
size_t morphTargets(const json& doc, int n) {
    const json& node = doc["nodes"][size_t(n)];
    if (!node.is_object() || !node.contains("mesh") || !node["mesh"].is_number_unsigned()) return 0;
    const size_t m = node["mesh"].get<size_t>();
    if (!doc.contains("meshes") || !doc["meshes"].is_array() || m >= doc["meshes"].size()) return 0;
    const json& mesh = doc["meshes"][m];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array() ||
        mesh["primitives"].empty() || !mesh["primitives"][0].is_object())
        return 0;
    const json& p = mesh["primitives"][0];
    return p.contains("targets") && p["targets"].is_array() ? p["targets"].size() : 0;
}

// Reads and checks sampler `s` of animation `a`; its problem, empty when none.
std::string readSampler(const json& doc, GltfBuffers& buffers, const json& js,
                        AnimationSampler& out) {
    if (!js.is_object() || !js.contains("input") || !js["input"].is_number_unsigned() ||
        !js.contains("output") || !js["output"].is_number_unsigned())
        return "has no input or output accessor";
    const std::string interpolation = js.value("interpolation", std::string("LINEAR"));
    if (interpolation == "LINEAR")
        out.interpolation = Interpolation::Linear;
    else if (interpolation == "STEP")
        out.interpolation = Interpolation::Step;
    else if (interpolation == "CUBICSPLINE")
        out.interpolation = Interpolation::CubicSpline;
    else
        return "its interpolation '" + interpolation + "' is not LINEAR, STEP or CUBICSPLINE";
    std::string error;
    int components = 0;
    if (!buffers.readFloats(js["input"].get<size_t>(), out.times, components, error))
        return "input " + error;
    if (components != 1) return "its input (key times) is not a SCALAR accessor";
    if (out.times.empty()) return "has no keys";
    for (size_t k = 0; k < out.times.size(); ++k) {
        if (!std::isfinite(out.times[k]))
            return "key time " + std::to_string(k) + " is not a finite number";
        if (k > 0 && !(out.times[k] > out.times[k - 1]))
            return "its key times do not increase (key " + std::to_string(k) + ", " +
                   std::to_string(out.times[k]) + " s, after " + std::to_string(out.times[k - 1]) +
                   " s)";
    }
    if (!buffers.readFloats(js["output"].get<size_t>(), out.values, out.components, error))
        return "output " + error;
    for (const float v : out.values)
        if (!std::isfinite(v)) return "its output holds a value that is not a finite number";
    (void)doc;
    return {};
}

// Checks that a sampler fits what channel `property` of node n needs; sets its shape.
std::string fitSampler(const json& doc, int n, AnimatedProperty property, AnimationSampler& s) {
    const size_t keys = s.times.size();
    const size_t perKey = s.interpolation == Interpolation::CubicSpline ? 3 : 1;
    const std::string cubic = perKey == 3 ? " (in-tangent, value, out-tangent)" : "";
    if (property == AnimatedProperty::Weights) {
        // Weights are SCALARs: one per morph target per key.
        const size_t targets = morphTargets(doc, n);
        if (s.components != 1) return "its output (weights) is not a SCALAR accessor";
        if (targets == 0) return "animates the weights of a node whose mesh has no morph targets";
        if (s.values.size() != keys * perKey * targets)
            return "has " + std::to_string(s.values.size()) + " weights for " +
                   std::to_string(keys) + " keys of " + std::to_string(targets) + " morph targets" +
                   cubic + ": " + std::to_string(keys * perKey * targets) + " expected";
        s.components = int(targets);
        return {};
    }
    const int want = property == AnimatedProperty::Rotation ? 4 : 3;
    if (s.components != want)
        return std::string("its output is not a ") + (want == 4 ? "VEC4" : "VEC3") + " accessor";
    if (s.values.size() != keys * perKey * size_t(want))
        return "has " + std::to_string(s.values.size() / size_t(want)) + " output values for " +
               std::to_string(keys) + " key times" + cubic + ": " + std::to_string(keys * perKey) +
               " expected";
    s.rotation = property == AnimatedProperty::Rotation;
    return {};
}

// Reads animation `a`'s channels and the samplers they use into `out`; its problem.
std::string readAnimation(const json& doc, GltfBuffers& buffers, const json& ja,
                          const std::vector<SceneNode>& nodes, Animation& out) {
    if (!ja.is_object() || !ja.contains("channels") || !ja["channels"].is_array() ||
        !ja.contains("samplers") || !ja["samplers"].is_array())
        return "has no channels or samplers array";
    const json& samplers = ja["samplers"];
    out.samplers.assign(samplers.size(), AnimationSampler{});
    std::vector<int> state(samplers.size(), 0); // 0 unread, 1 read (and its property)
    std::vector<AnimatedProperty> usedAs(samplers.size());
    std::vector<int> usedBy(samplers.size(), -1);
    for (size_t c = 0; c < ja["channels"].size(); ++c) {
        const json& jc = ja["channels"][c];
        const std::string where = "channel " + std::to_string(c);
        if (!jc.is_object() || !jc.contains("sampler") || !jc["sampler"].is_number_unsigned() ||
            jc["sampler"].get<size_t>() >= samplers.size())
            return where + ": its sampler does not exist";
        if (!jc.contains("target") || !jc["target"].is_object()) return where + ": has no target";
        const json& target = jc["target"];
        const std::string path = target.value("path", std::string());
        AnimationChannel ch;
        ch.sampler = int(jc["sampler"].get<size_t>());
        if (path == "translation")
            ch.property = AnimatedProperty::Translation;
        else if (path == "rotation")
            ch.property = AnimatedProperty::Rotation;
        else if (path == "scale")
            ch.property = AnimatedProperty::Scale;
        else if (path == "weights")
            ch.property = AnimatedProperty::Weights;
        else
            return where + ": its target path '" + path + "' is not one glTF 2.0 defines";
        if (!target.contains("node")) continue; // glTF: a channel without a node is ignored
        if (!target["node"].is_number_unsigned() || target["node"].get<size_t>() >= nodes.size())
            return where + ": its target node " + target["node"].dump() + " does not exist";
        ch.node = int(target["node"].get<size_t>());
        if (nodes[size_t(ch.node)].hasMatrix && ch.property != AnimatedProperty::Weights)
            return where + ": node " + std::to_string(ch.node) +
                   " is given by a matrix, which glTF does not allow to animate";
        const size_t s = size_t(ch.sampler);
        const std::string sampler = "sampler " + std::to_string(s);
        if (state[s] == 0) {
            if (std::string p = readSampler(doc, buffers, samplers[s], out.samplers[s]); !p.empty())
                return sampler + ": " + p;
            if (std::string p = fitSampler(doc, ch.node, ch.property, out.samplers[s]); !p.empty())
                return sampler + " (" + where + ", " + path + "): " + p;
            state[s] = 1;
            usedAs[s] = ch.property;
            usedBy[s] = ch.node;
        } else if (usedAs[s] != ch.property ||
                   (ch.property == AnimatedProperty::Weights &&
                    morphTargets(doc, ch.node) != morphTargets(doc, usedBy[s]))) {
            return sampler + " drives properties of different shapes (" + where + ")";
        }
        out.channels.push_back(ch);
    }
    bool any = false;
    for (size_t s = 0; s < samplers.size(); ++s) {
        if (state[s] == 0) continue;
        const auto& t = out.samplers[s].times;
        out.start = any ? std::min(out.start, double(t.front())) : double(t.front());
        out.end = any ? std::max(out.end, double(t.back())) : double(t.back());
        any = true;
    }
    return {};
}

} // namespace

std::vector<int> gltfChildren(const json& doc, int n) {
    std::vector<int> out;
    const json& nodes = doc["nodes"];
    const json& node = nodes[size_t(n)];
    if (!node.is_object() || !node.contains("children") || !node["children"].is_array()) return out;
    for (const auto& c : node["children"])
        if (c.is_number_unsigned() && c.get<size_t>() < nodes.size())
            out.push_back(int(c.get<size_t>()));
    return out;
}

std::vector<int> gltfSceneRoots(const json& doc) {
    std::vector<int> roots;
    if (!doc.contains("scenes") || !doc["scenes"].is_array() || doc["scenes"].empty()) return roots;
    const size_t index =
        doc.contains("scene") && doc["scene"].is_number_unsigned() ? doc["scene"].get<size_t>() : 0;
    if (index >= doc["scenes"].size() || !doc["scenes"][index].is_object()) return roots;
    const json& scene = doc["scenes"][index];
    const size_t count = doc.contains("nodes") && doc["nodes"].is_array() ? doc["nodes"].size() : 0;
    if (scene.contains("nodes") && scene["nodes"].is_array())
        for (const auto& n : scene["nodes"])
            if (n.is_number_unsigned() && n.get<size_t>() < count)
                roots.push_back(int(n.get<size_t>()));
    return roots;
}

bool gltfNodeTree(const json& doc, std::vector<SceneNode>& nodes, std::vector<int>& order,
                  std::string& error) {
    nodes.clear();
    order.clear();
    if (!doc.contains("nodes") || !doc["nodes"].is_array()) return true;
    const json& jn = doc["nodes"];
    nodes.resize(jn.size());
    for (size_t n = 0; n < jn.size(); ++n) {
        const json& node = jn[n];
        SceneNode& out = nodes[n];
        if (!node.is_object()) continue;
        if (node.contains("name") && node["name"].is_string())
            out.name = node["name"].get<std::string>();
        double v[16];
        if (numbers(node, "matrix", 16, v)) {
            out.hasMatrix = true;
            out.matrix = glm::make_mat4(v);
        }
        if (numbers(node, "translation", 3, v)) out.translation = glm::dvec3(v[0], v[1], v[2]);
        if (numbers(node, "rotation", 4, v)) out.rotation = glm::dquat(v[3], v[0], v[1], v[2]);
        if (numbers(node, "scale", 3, v)) out.scale = glm::dvec3(v[0], v[1], v[2]);
    }
    for (size_t n = 0; n < jn.size(); ++n)
        for (const int c : gltfChildren(doc, int(n))) {
            if (nodes[size_t(c)].parent >= 0 || c == int(n)) {
                error = "node " + std::to_string(c) + " is the child of two nodes, or its own";
                return false;
            }
            nodes[size_t(c)].parent = int(n);
        }
    // Parents first: from each root down, with an explicit stack; a node never reached lies on
    // a cycle.
    for (size_t n = 0; n < nodes.size(); ++n) {
        if (nodes[n].parent >= 0) continue;
        std::vector<int> stack = {int(n)};
        while (!stack.empty()) {
            const int at = stack.back();
            stack.pop_back();
            order.push_back(at);
            for (const int c : gltfChildren(doc, at))
                stack.push_back(c);
        }
    }
    if (order.size() != nodes.size()) {
        error = "the nodes form a cycle, not a tree";
        return false;
    }
    return true;
}

bool gltfSkins(const json& doc, GltfBuffers& buffers, const std::vector<SceneNode>& nodes,
               std::vector<SceneSkin>& skins, std::string& error) {
    skins.clear();
    if (!doc.contains("skins") || !doc["skins"].is_array()) return true;
    for (size_t k = 0; k < doc["skins"].size(); ++k) {
        const json& js = doc["skins"][k];
        const std::string which = "skin " + std::to_string(k) + ": ";
        SceneSkin skin;
        if (!js.is_object() || !js.contains("joints") || !js["joints"].is_array() ||
            js["joints"].empty()) {
            error = which + "has no joints";
            return false;
        }
        for (const json& j : js["joints"]) {
            if (!j.is_number_unsigned() || j.get<size_t>() >= nodes.size()) {
                error = which + "joint " + j.dump() + " is not a node";
                return false;
            }
            skin.joints.push_back(int(j.get<size_t>()));
        }
        skin.inverseBind.assign(skin.joints.size(), glm::dmat4(1.0));
        if (js.contains("inverseBindMatrices")) {
            std::vector<float> m;
            int components = 0;
            if (!js["inverseBindMatrices"].is_number_unsigned() ||
                !buffers.readFloats(js["inverseBindMatrices"].get<size_t>(), m, components,
                                    error)) {
                error = which +
                        "inverseBindMatrices: " + (error.empty() ? "not an accessor index" : error);
                return false;
            }
            if (components != 16 || m.size() < 16 * skin.joints.size()) {
                error =
                    which + "inverseBindMatrices is not a MAT4 accessor of one matrix per joint";
                return false;
            }
            for (size_t j = 0; j < skin.joints.size(); ++j)
                for (int c = 0; c < 16; ++c) {
                    if (!std::isfinite(m[16 * j + size_t(c)])) {
                        error = which + "an inverse bind matrix holds a value that is not finite";
                        return false;
                    }
                    skin.inverseBind[j][c / 4][c % 4] = double(m[16 * j + size_t(c)]);
                }
        }
        skins.push_back(std::move(skin));
    }
    return true;
}

std::vector<Animation> gltfAnimations(const json& doc, GltfBuffers& buffers,
                                      const std::vector<SceneNode>& nodes) {
    std::vector<Animation> out;
    if (!doc.contains("animations") || !doc["animations"].is_array()) return out;
    for (size_t a = 0; a < doc["animations"].size(); ++a) {
        const json& ja = doc["animations"][a];
        Animation anim;
        anim.name = ja.is_object() && ja.contains("name") && ja["name"].is_string()
                        ? ja["name"].get<std::string>()
                        : "animation " + std::to_string(a);
        anim.problem = readAnimation(doc, buffers, ja, nodes, anim);
        if (!anim.problem.empty()) {
            anim.samplers.clear();
            anim.channels.clear();
        }
        out.push_back(std::move(anim));
    }
    return out;
}

} // namespace dhdr::detail
