// The binary data of a glTF file (its buffers and accessors), read from the file itself for what
// Assimp 5.2 gets wrong or does not keep: animation samplers (and, later, skins and morph
// targets).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace dhdr::detail {

class GltfBuffers {
public:
    // `path`: the .gltf or .glb file whose JSON is `doc`. Buffers are read when first used.
    GltfBuffers(std::string path, const nlohmann::json& doc)
        : m_path(std::move(path)), m_doc(doc) {}

    // The elements of accessor `index` as floats, `components` per element (SCALAR 1 ... MAT4
    // 16): float components as they are, normalized integers mapped as glTF 2.0 §3.11 says
    // (max(c / (2^(n−1) − 1), −1) signed, c / (2^n − 1) unsigned), other integers as their value.
    // False with `error` saying what is wrong (no such accessor, a bufferView past its buffer, a
    // buffer that cannot be read...). Sparse accessors are applied.
    bool readFloats(size_t index, std::vector<float>& out, int& components, std::string& error);

    // The elements of an index accessor (unsigned byte, short or int SCALARs), exactly.
    bool readIndices(size_t index, std::vector<std::uint32_t>& out, std::string& error);

    // The encoded bytes (PNG, JPEG...) of image `index` when the file holds them itself, in a
    // bufferView or a base64 data URI. False with `error` saying what is wrong (no such image, one
    // that names an outside file, a bufferView past its buffer...).
    bool readImage(size_t index, std::vector<std::uint8_t>& out, std::string& error);

private:
    // Where an accessor's elements lie: null `base` for an accessor without a bufferView.
    struct Span {
        const std::uint8_t* base = nullptr;
        size_t stride = 0, size = 0;
        int type = 0;
    };
    bool locate(const nlohmann::json& accessor, size_t count, int components, Span& span,
                std::string& error);
    bool buffer(size_t index, const std::vector<std::uint8_t>*& bytes, std::string& error);
    bool readDense(const nlohmann::json& accessor, size_t count, int components,
                   std::vector<float>& out, std::string& error);

    std::string m_path;
    const nlohmann::json& m_doc;
    std::vector<std::vector<std::uint8_t>> m_buffers;
    std::vector<char> m_loaded;
};

// Components of an accessor type ("VEC3": 3), 0 for an unknown one.
int gltfComponents(const std::string& type);

} // namespace dhdr::detail
