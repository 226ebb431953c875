#include <algorithm>
#include <cmath>
#include <dhdr/deferred/geometry/surface.h>

namespace dhdr {

double positionError(const glm::dvec3& P, const glm::dvec3 vertices[3],
                     const glm::dmat4* instance) {
    constexpr double ulp = 0x1p-24; // float's unit roundoff: ½ ulp relative
    double largest = 0.0, extent = 0.0;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec3 a = glm::abs(vertices[i]);
        const glm::dvec3 e = glm::abs(vertices[(i + 1) % 3] - vertices[i]);
        largest = std::max({largest, a.x, a.y, a.z});
        extent = std::max({extent, e.x, e.y, e.z});
    }
    const glm::dvec3 p = glm::abs(P);
    const double size = std::max({p.x, p.y, p.z});
    double kernel = largest + extent;
    // An instance's triangles stand where float(M) puts them, and a ray is taken into node
    // space by the float inverse: roundings of |b| and of |P| (which cancel to the node-space
    // point) beyond the world triangle's.
    if (instance) {
        const glm::dvec3 b = glm::abs(glm::dvec3((*instance)[3]));
        kernel += size + std::max({b.x, b.y, b.z});
    }
    return ulp * size + kKernelUlps * 2.0 * ulp * kernel;
}

glm::dvec3 terminatorLift(const glm::dvec3 vertices[3], const glm::dvec3 normals[3],
                          const glm::dvec3& w, const glm::dvec3& P, const glm::dvec3& geometric) {
    if (normals[0] == normals[1] && normals[1] == normals[2]) return glm::dvec3(0.0);
    glm::dvec3 lift(0.0);
    for (int i = 0; i < 3; ++i)
        lift += w[i] * std::max(0.0, glm::dot(vertices[i] - P, normals[i])) * normals[i];
    const double below = glm::dot(lift, geometric);
    if (below < 0.0) lift -= below * geometric;
    return lift;
}

namespace {

// `n` (unit) if it faces the viewer (`toViewer`, unit) by at least a cosine of kGrazing, else
// bent towards it in their plane until it does; `fallback` when that leaves no direction.
constexpr double kGrazing = 1e-3; // cosine left between a bent normal and the horizon
glm::dvec3 facingViewer(glm::dvec3 n, const glm::dvec3& toViewer, const glm::dvec3& fallback) {
    const double facing = glm::dot(n, toViewer);
    if (facing >= kGrazing) return n;
    n += (kGrazing - facing) * toViewer;
    return glm::dot(n, n) > 1e-20 ? glm::normalize(n) : fallback;
}

// glTF 2.0 §3.9.3: n = normalize(T·x + B·y + N·z) with (x, y, z) = 2·texel − 1 and x, y
// scaled by normalTexture.scale. A mapped normal that faces away from the viewer is bent back
// to just in front of it, in the plane of it and the view direction (as Cycles'
// ensure_valid_reflection does), not turned round: negating it would mirror the map's slope.
glm::dvec3 mappedNormal(const Mesh& mesh, const glm::uvec3& tri, double w0, double w1, double w2,
                        const glm::vec4& texel, double scale, const SurfaceSample& s,
                        const glm::dvec3& direction) {
    const glm::dvec3 T = w0 * glm::dvec3(mesh.tangents[tri[0]]) +
                         w1 * glm::dvec3(mesh.tangents[tri[1]]) +
                         w2 * glm::dvec3(mesh.tangents[tri[2]]);
    const glm::dvec3 B = w0 * glm::dvec3(mesh.bitangents[tri[0]]) +
                         w1 * glm::dvec3(mesh.bitangents[tri[1]]) +
                         w2 * glm::dvec3(mesh.bitangents[tri[2]]);
    const glm::dvec3 t = glm::dvec3(texel) * 2.0 - 1.0;
    const glm::dvec3 mapped = T * (t.x * scale) + B * (t.y * scale) + s.interpolated * t.z;
    if (!(glm::dot(mapped, mapped) > 1e-20)) return s.normal;
    return facingViewer(glm::normalize(mapped), -direction, s.normal);
}

// The roughness of a surface whose normal map was filtered over the pixel's footprint to
// `texel`: the normals the footprint covers spread, and the filtered vector 2·texel − 1 is
// shorter than a texel's (`unit`) by as much. Taken as a von Mises-Fisher lobe of concentration
// κ = (3r − r³)/(1 − r²) for the relative length r (Han et al. 2007, "Frequency Domain Normal
// Map Filtering", eq. 6), whose slope variance 1/κ per axis widens the GGX lobe: α'² = α² + 2/κ
// (Toksvig's idea; α = roughness²).
float filteredNormalRoughness(float roughness, const glm::vec4& texel, float unit) {
    const double r =
        std::min(glm::length(glm::dvec3(glm::vec3(texel)) * 2.0 - 1.0) / double(unit), 1.0);
    if (!(r < 1.0 - 1e-6)) return roughness;
    const double kappa = (3.0 * r - r * r * r) / (1.0 - r * r);
    const double alpha = double(roughness) * double(roughness);
    const double widened = std::min(alpha * alpha + 2.0 / kappa, 1.0);
    return float(std::sqrt(std::sqrt(widened)));
}

// KHR_materials_clearcoat's textures: the weight (R), roughness (G) and the coat's own normal
// map, in the base's tangent frame.
void applyClearcoat(const Scene& scene, const Mesh& mesh, int triangle, double w1, double w2,
                    const Ray& ray, const MeshUvs& uvs, SurfaceSample& s) {
    const Material& m = *s.material;
    if (m.clearcoatTexture.texture >= 0)
        s.clearcoat *= sampleTexture(scene, m.clearcoatTexture, uvs).r;
    if (m.clearcoatRoughnessTexture.texture >= 0)
        s.clearcoatRoughness *= sampleTexture(scene, m.clearcoatRoughnessTexture, uvs).g;
    if (m.clearcoatNormalTexture.texture >= 0 && !mesh.tangents.empty()) {
        const glm::uvec3 tri = mesh.triangles[size_t(triangle)];
        const glm::vec4 texel = sampleTexture(scene, m.clearcoatNormalTexture, uvs);
        SurfaceSample unmapped = s;
        unmapped.normal = s.interpolated;
        s.clearcoatNormal = mappedNormal(mesh, tri, 1.0 - w1 - w2, w1, w2, texel,
                                         double(m.clearcoatNormalScale), unmapped, ray.direction);
    }
}

// KHR_materials_specular's textures (its README, "Implementation"): specularTexture's A scales
// specularFactor and specularColorTexture's RGB specularColorFactor, in F0 and F90 alike.
void applySpecular(const Scene& scene, const MeshUvs& uvs, SurfaceSample& s) {
    const Material& m = *s.material;
    float specular = m.specularFactor;
    glm::vec3 color = m.specularColor;
    if (m.specularTexture.texture >= 0) specular *= sampleTexture(scene, m.specularTexture, uvs).a;
    if (m.specularColorTexture.texture >= 0)
        color *= glm::vec3(sampleTexture(scene, m.specularColorTexture, uvs));
    s.dielectricF0 = dielectricF0(m.ior, color, specular);
    s.dielectricF90 = specular;
}

// KHR_materials_pbrSpecularGlossiness with its specularGlossinessTexture: the conversion to
// metal-rough made with this texel (1 where the mesh has no UVs) scaling the factors, over the
// diffuse colour already in s.albedo (× vertex colour × diffuse texture, as its README says).
void applySpecularGlossiness(const Material& m, const glm::vec4& texel, SurfaceSample& s) {
    const MetalRoughFromSpecGloss c =
        specGlossAsMetalRough(s.albedo, m.glossSpecular * glm::vec3(texel), m.glossiness * texel.a);
    s.albedo = c.baseColor;
    s.roughness = c.roughness;
    s.dielectricF0 = c.f0;
    s.dielectricF90 = 1.0f;
}

// The material's factors at the hit times its textures (on their UV sets) and the vertex
// colour, into `s`.
void applyMaterial(const Scene& scene, const Mesh& mesh, int triangle, double w1, double w2,
                   const Ray& ray, const UvFootprint* footprint, SurfaceSample& s) {
    const Material& m = *s.material;
    const glm::vec4 color = vertexColor(mesh, triangle, w1, w2);
    s.albedo = m.baseColor * glm::vec3(color);
    s.emission = m.emission;
    s.roughness = m.roughness;
    s.metallic = m.metallic;
    s.dielectricF0 = m.dielectricF0();
    s.dielectricF90 = m.dielectricF90();
    s.clearcoat = m.clearcoat;
    s.clearcoatRoughness = m.clearcoatRoughness;
    s.clearcoatNormal = s.interpolated;
    s.sheenColor = m.sheenColor;
    s.sheenRoughness = m.sheenRoughness;
    s.transmission = m.transmission;
    if (mesh.uvs.empty()) {
        if (m.specularGlossinessTexture.texture >= 0)
            applySpecularGlossiness(m, glm::vec4(1.0f), s);
        return;
    }
    MeshUvs uvs = meshUvs(mesh, triangle, w1, w2);
    uvs.footprint = footprint;
    auto sample = [&](const TextureRef& ref) { return sampleTexture(scene, ref, uvs); };
    if (m.baseColorTexture.texture >= 0) s.albedo *= glm::vec3(sample(m.baseColorTexture));
    if (m.emissiveTexture.texture >= 0) s.emission *= glm::vec3(sample(m.emissiveTexture));
    if (m.metallicRoughnessTexture.texture >= 0) {
        const glm::vec4 mr = sample(m.metallicRoughnessTexture);
        s.roughness *= mr.g;
        s.metallic *= mr.b;
    }
    if (m.occlusionTexture.texture >= 0)
        s.occlusion = 1.0f + m.occlusionStrength * (sample(m.occlusionTexture).r - 1.0f);
    if (m.specularTexture.texture >= 0 || m.specularColorTexture.texture >= 0)
        applySpecular(scene, uvs, s);
    if (m.specularGlossinessTexture.texture >= 0)
        applySpecularGlossiness(m, sample(m.specularGlossinessTexture), s);
    if (m.clearcoat > 0.0f) applyClearcoat(scene, mesh, triangle, w1, w2, ray, uvs, s);
    // KHR_materials_sheen's textures: the colour (RGB) and the roughness (A).
    if (m.sheenColorTexture.texture >= 0) s.sheenColor *= glm::vec3(sample(m.sheenColorTexture));
    if (m.sheenRoughnessTexture.texture >= 0) s.sheenRoughness *= sample(m.sheenRoughnessTexture).a;
    if (m.transmissionTexture.texture >= 0) s.transmission *= sample(m.transmissionTexture).r;
    if (m.normalTexture.texture >= 0 && !mesh.tangents.empty()) {
        const glm::uvec3 tri = mesh.triangles[size_t(triangle)];
        const glm::vec4 texel = sample(m.normalTexture);
        s.normal = mappedNormal(mesh, tri, 1.0 - w1 - w2, w1, w2, texel, double(m.normalScale), s,
                                ray.direction);
        if (textureMinified(scene, m.normalTexture, uvs))
            s.roughness = filteredNormalRoughness(
                s.roughness, texel, scene.textures[size_t(m.normalTexture.texture)].normalLength);
    }
}

// KHR_materials_unlit: the base colour shown as it is (its emission), nothing reflected.
void applyUnlit(SurfaceSample& s) {
    s.emission = s.albedo;
    s.albedo = glm::vec3(0.0f);
    s.metallic = 0.0f;
    s.dielectricF0 = glm::vec3(0.0f);
    s.dielectricF90 = 0.0f;
}

} // namespace

SurfaceSample surfaceAt(const Scene& scene, const Ray& ray, const RayHit& hit,
                        const UvFootprint* footprint) {
    SurfaceSample s = surfaceGeometryAt(scene, ray, hit);
    if (hit.mesh == kGroundPlaneHit) return s;
    const Mesh& mesh = scene.meshes[size_t(hit.mesh)];
    applyMaterial(scene, mesh, hit.triangle, hit.u, hit.v, ray, footprint, s);
    if (s.material->unlit) applyUnlit(s);
    return s;
}

SurfaceSample surfaceGeometryAt(const Scene& scene, const Ray& ray, const RayHit& hit) {
    if (hit.mesh == kGroundPlaneHit) {
        SurfaceSample s;
        s.position = ray.origin + hit.t * ray.direction;
        s.position.y = scene.groundPlaneY; // on the plane exactly
        s.normal = glm::dvec3(0.0, ray.direction.y < 0.0 ? 1.0 : -1.0, 0.0);
        s.interpolated = s.geometric = s.normal;
        // Only the rounding of x and z: y is exact, and shadow rays meet the plane
        // analytically (RayCaster), not through Embree.
        s.positionError = 0x1p-24 * std::max({std::abs(s.position.x), std::abs(s.position.z),
                                              std::abs(s.position.y)});
        s.material = &scene.materials[size_t(scene.groundMaterial)];
        s.albedo = s.material->baseColor;
        s.emission = glm::vec3(0.0f);
        s.roughness = s.material->roughness;
        s.metallic = s.material->metallic;
        return s;
    }
    const Mesh& mesh = scene.meshes[size_t(hit.mesh)];
    const glm::uvec3 tri = mesh.triangles[size_t(hit.triangle)];
    const double w1 = hit.u, w2 = hit.v, w0 = 1.0 - w1 - w2;
    SurfaceSample s;
    // From the vertices rather than along the ray: the hit distance's error (Embree's
    // approximate reciprocal, its last bits kernel-dependent) would move P off the plane in
    // proportion to the camera distance; the barycentrics' error only moves it along it.
    const glm::dvec3 vertices[3] = {glm::dvec3(mesh.positions[tri[0]]),
                                    glm::dvec3(mesh.positions[tri[1]]),
                                    glm::dvec3(mesh.positions[tri[2]])};
    s.position = w0 * vertices[0] + w1 * vertices[1] + w2 * vertices[2];
    s.positionError =
        positionError(s.position, vertices, mesh.instance ? &*mesh.instance : nullptr);
    glm::dvec3 face = glm::cross(vertices[1] - vertices[0], vertices[2] - vertices[0]);
    // A degenerate triangle (Embree reports none, but a sliver may underflow): the ray's own
    // direction stands in.
    face = glm::dot(face, face) > 0.0 ? glm::normalize(face) : -ray.direction;
    s.geometric = glm::dot(face, ray.direction) > 0.0 ? -face : face;
    const glm::dvec3 n0(mesh.normals[tri[0]]), n1(mesh.normals[tri[1]]), n2(mesh.normals[tri[2]]);
    glm::dvec3 n = w0 * n0 + w1 * n1 + w2 * n2;
    // A vertex without a normal (zero in the file), or normals that cancel: the triangle's own.
    const auto missing = [](const glm::dvec3& v) { return glm::dot(v, v) < 0.25; };
    const bool flat = missing(n0) || missing(n1) || missing(n2) || !(glm::dot(n, n) >= 1e-20);
    n = flat ? face : glm::normalize(n);
    // Which side of its triangle the ray met, by the triangle (its face turned to the side the
    // file's normals are on), not by the interpolated normal: near a silhouette that one can
    // face away from a ray that meets the front, and turning it round shaded the front as the
    // back (single bright pixels where the light is behind the silhouette).
    const glm::dvec3 outward = glm::dot(face, n) < 0.0 ? -face : face;
    s.backFace = glm::dot(outward, ray.direction) > 0.0;
    const double side = s.backFace ? -1.0 : 1.0;
    // The contract's normals face the camera: bent to just in front of the viewer where the
    // interpolation leaves them behind (as mappedNormal, and Cycles' ensure_valid_reflection).
    s.normal = facingViewer(side * n, -ray.direction, s.geometric);
    s.interpolated = s.normal;
    if (!flat) {
        const glm::dvec3 normals[3] = {side * glm::normalize(n0), side * glm::normalize(n1),
                                       side * glm::normalize(n2)};
        const glm::dvec3 w(w0, w1, w2);
        s.lift = terminatorLift(vertices, normals, w, s.position, s.geometric);
    }

    s.material = &scene.materials[size_t(mesh.material)];
    return s;
}

} // namespace dhdr
