#include <cmath>
#include <dhdr/deferred/geometry/uv_footprint.h>
#include <glm/geometric.hpp>

namespace dhdr {

UvFootprint uvFootprint(const Scene& scene, const RayHit& hit, const Ray& centre, const Ray& across,
                        const Ray& down, TextureFilter filter) {
    UvFootprint f;
    f.filter = filter;
    if (hit.mesh == kGroundPlaneHit) return f;
    const Mesh& mesh = scene.meshes[size_t(hit.mesh)];
    if (mesh.uvs.empty()) return f;
    const glm::uvec3 tri = mesh.triangles[size_t(hit.triangle)];
    const glm::dvec3 p0(mesh.positions[tri[0]]), e1 = glm::dvec3(mesh.positions[tri[1]]) - p0,
                                                 e2 = glm::dvec3(mesh.positions[tri[2]]) - p0;
    const glm::dvec3 n = glm::cross(e1, e2);
    const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const double det = d11 * d22 - d12 * d12;
    if (!(det > 0.0)) return f; // degenerate: no plane to meet
    // Where `ray` meets the plane; false where it does not (in front of its origin).
    auto meet = [&](const Ray& ray, glm::dvec3& at) {
        const double t = glm::dot(n, p0 - ray.origin) / glm::dot(n, ray.direction);
        at = ray.origin + t * ray.direction;
        return std::isfinite(t) && t > 0.0;
    };
    // The centre ray met again rather than Embree's float barycentrics used: the footprint
    // then owes nothing to the kernel's last bits.
    glm::dvec3 P, X, Y;
    const bool met = meet(centre, P) && meet(across, X) && meet(down, Y);
    // The barycentric change (w1, w2) from P to Q; false past 10⁸ triangles (or NaN).
    auto change = [&](const glm::dvec3& Q, glm::dvec2& dw) {
        const glm::dvec3 d = Q - P;
        const double a = glm::dot(d, e1), b = glm::dot(d, e2);
        dw = glm::dvec2(d22 * a - d12 * b, d11 * b - d12 * a) / det;
        return std::abs(dw.x) < 1e8 && std::abs(dw.y) < 1e8;
    };
    glm::dvec2 dx, dy;
    if (!met || !change(X, dx) || !change(Y, dy)) {
        constexpr float kEdgeOn = 1e8f; // texture widths: the smallest mip level
        for (int s = 0; s < 2; ++s) {
            f.dx[s] = glm::vec2(kEdgeOn, 0.0f);
            f.dy[s] = glm::vec2(0.0f, kEdgeOn);
        }
        return f;
    }
    auto uvChange = [&](const std::vector<glm::vec2>& uv, const glm::dvec2& dw) {
        const glm::dvec2 u0(uv[tri[0]]);
        return glm::vec2(dw.x * (glm::dvec2(uv[tri[1]]) - u0) +
                         dw.y * (glm::dvec2(uv[tri[2]]) - u0));
    };
    f.dx[0] = uvChange(mesh.uvs, dx);
    f.dy[0] = uvChange(mesh.uvs, dy);
    f.dx[1] = mesh.uvs1.empty() ? f.dx[0] : uvChange(mesh.uvs1, dx);
    f.dy[1] = mesh.uvs1.empty() ? f.dy[0] : uvChange(mesh.uvs1, dy);
    return f;
}

} // namespace dhdr
