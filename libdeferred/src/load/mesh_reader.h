// A scene's meshes: each triangle mesh Assimp gives a node, into world space (positions,
// normals, both UV sets, vertex colours, tangent frames), flat-shaded where the file has no
// normals, into Scene::meshes; morphed and skinned ones from the file itself (RigLoader).
#pragma once

#include "load/rig_loader.h"

#include <assimp/scene.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_rig.h>
#include <glm/glm.hpp>
#include <string>

namespace dhdr::detail {

class MeshReader {
public:
    // How a file's vertex colours are read: glTF's COLOR_0 multiplies the base colour; other
    // formats' colours are not part of their materials. Assimp 5.2 gives an RGB (VEC3)
    // COLOR_0 an alpha of 0 instead of 1 (it copies three components into four zeroed ones).
    struct VertexColors {
        bool read = false;
        bool rgbInFile = false; // the file has RGB COLOR_0 accessors
    };

    // Meshes of the file at `path` (for messages), into `scene`, kept in `rig`.
    MeshReader(const std::string& path, Scene& scene, RigLoader& rig, VertexColors colors)
        : m_path(path), m_scene(scene), m_rig(rig), m_colors(colors) {}

    // Adds `am`, the `primitive`-th mesh of `node` (the glTF primitive it is), as part of
    // object `object`; points and lines are skipped. False with `error` for a vertex that is
    // not finite in world space or a deformed primitive the file gets wrong.
    bool add(const aiMesh& am, const aiNode& node, unsigned primitive, const glm::dmat4& world,
             const glm::dmat3& normalMatrix, int object, std::string& error);

    // How many of the file's vertex normals had zero length (or were not finite).
    long long zeroNormals() const { return m_zeroNormals; }

private:
    bool readVertices(const aiMesh& am, const aiNode& node, const glm::dmat4& world,
                      const glm::dmat3& normalMatrix, Mesh& mesh, std::string& error);
    void readColors(const aiMesh& am, Mesh& mesh) const;
    void keep(Mesh mesh, MeshRest rest);

    const std::string& m_path;
    Scene& m_scene;
    RigLoader& m_rig;
    VertexColors m_colors;
    long long m_zeroNormals = 0;
};

} // namespace dhdr::detail
