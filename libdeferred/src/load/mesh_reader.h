// A scene's meshes: each triangle mesh Assimp gives a node, into world space (positions,
// normals, UVs, tangent frames), flat-shaded where the file has no normals, into
// Scene::meshes; morphed and skinned ones from the file itself (RigLoader).
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
    // Meshes of the file at `path` (for messages), into `scene`, kept in `rig`.
    MeshReader(const std::string& path, Scene& scene, RigLoader& rig)
        : m_path(path), m_scene(scene), m_rig(rig) {}

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
    void keep(Mesh mesh, MeshRest rest);

    const std::string& m_path;
    Scene& m_scene;
    RigLoader& m_rig;
    long long m_zeroNormals = 0;
};

} // namespace dhdr::detail
