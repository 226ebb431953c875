#include <dhdr/deferred/surface.h>

namespace dhdr {

SurfaceSample surfaceAt(const Scene& scene, const Ray& ray, const RayHit& hit) {
    if (hit.mesh == kGroundPlaneHit) {
        SurfaceSample s;
        s.position = ray.origin + hit.t * ray.direction;
        s.position.y = scene.groundPlaneY; // on the plane exactly
        s.normal = glm::dvec3(0.0, ray.direction.y < 0.0 ? 1.0 : -1.0, 0.0);
        s.geometric = s.normal;
        s.material = &scene.materials[size_t(scene.groundMaterial)];
        s.albedo = s.material->baseColor;
        s.emission = glm::vec3(0.0f);
        return s;
    }
    const Mesh& mesh = scene.meshes[size_t(hit.mesh)];
    const glm::uvec3 tri = mesh.triangles[size_t(hit.triangle)];
    const double w1 = hit.u, w2 = hit.v, w0 = 1.0 - w1 - w2;
    SurfaceSample s;
    s.position = ray.origin + hit.t * ray.direction;
    const glm::dvec3 n0(mesh.normals[tri[0]]), n1(mesh.normals[tri[1]]), n2(mesh.normals[tri[2]]);
    s.normal = w0 * n0 + w1 * n1 + w2 * n2;
    // A vertex without a normal (zero in the file), or normals that cancel: the triangle's own.
    const auto missing = [](const glm::dvec3& n) { return glm::dot(n, n) < 0.25; };
    if (missing(n0) || missing(n1) || missing(n2) || glm::dot(s.normal, s.normal) < 1e-20) {
        const glm::dvec3 a(mesh.positions[tri[0]]), b(mesh.positions[tri[1]]),
            c(mesh.positions[tri[2]]);
        s.normal = glm::cross(b - a, c - a);
    }
    s.normal = glm::normalize(s.normal);
    // The contract's normals face the camera: a back face is shaded as seen.
    s.backFace = glm::dot(s.normal, ray.direction) > 0.0;
    if (s.backFace) s.normal = -s.normal;
    s.geometric = s.normal;

    s.material = &scene.materials[size_t(mesh.material)];
    const Material& m = *s.material;
    s.albedo = m.baseColor;
    s.emission = m.emission;
    if (mesh.uvs.empty()) return s;
    const glm::vec2 uv =
        float(w0) * mesh.uvs[tri[0]] + float(w1) * mesh.uvs[tri[1]] + float(w2) * mesh.uvs[tri[2]];
    auto sample = [&](const TextureRef& ref) {
        return scene.textures[size_t(ref.texture)].sample(ref.transform.apply(uv));
    };
    if (m.baseColorTexture.texture >= 0) s.albedo *= glm::vec3(sample(m.baseColorTexture));
    if (m.emissiveTexture.texture >= 0) s.emission *= glm::vec3(sample(m.emissiveTexture));
    if (m.normalTexture.texture >= 0 && !mesh.tangents.empty()) {
        // glTF 2.0 §3.9.3: n = normalize(T·x + B·y + N·z) with (x, y, z) = (2·texel − 1) and
        // x, y scaled by normalTexture.scale.
        const glm::dvec3 T = w0 * glm::dvec3(mesh.tangents[tri[0]]) +
                             w1 * glm::dvec3(mesh.tangents[tri[1]]) +
                             w2 * glm::dvec3(mesh.tangents[tri[2]]);
        const glm::dvec3 B = w0 * glm::dvec3(mesh.bitangents[tri[0]]) +
                             w1 * glm::dvec3(mesh.bitangents[tri[1]]) +
                             w2 * glm::dvec3(mesh.bitangents[tri[2]]);
        const glm::dvec3 t = glm::dvec3(sample(m.normalTexture)) * 2.0 - 1.0;
        const glm::dvec3 mapped = T * (t.x * double(m.normalScale)) +
                                  B * (t.y * double(m.normalScale)) + s.geometric * t.z;
        if (glm::dot(mapped, mapped) > 1e-20) s.normal = glm::normalize(mapped);
        if (glm::dot(s.normal, ray.direction) > 0.0) s.normal = -s.normal;
    }
    return s;
}

} // namespace dhdr
