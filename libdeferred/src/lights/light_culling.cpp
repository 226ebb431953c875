#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <cmath>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/lights/light_bounds.h>
#include <dhdr/deferred/lights/light_culling.h>

namespace dhdr {

LightBound lightBound(const Light& light) {
    LightBound b{light.position, light.range};
    if (light.type == LightType::Spot) {
        // The cone of half-angle θ cut at the range r lies in the sphere of radius
        // r / (2 cos θ) centred that far along the axis: apex and rim are on it, the rest of
        // the spherical sector inside. Smaller than the range sphere while θ < 60°.
        const float cosOuter = std::cos(light.outerConeAngle);
        const float radius = light.range / (2.0f * cosOuter);
        if (radius < light.range) b = {light.position + light.direction * radius, radius};
    }
    return b;
}

namespace {

constexpr int kSlices = 32;

int sliceIndex(float z, float zmin, float zmax) {
    if (!(zmax > zmin)) return 0;
    const int s = int((z - zmin) / (zmax - zmin) * float(kSlices));
    return std::clamp(s, 0, kSlices - 1);
}

// Bits s0..s1 set.
std::uint32_t sliceRange(int s0, int s1) {
    const std::uint32_t upTo = s1 >= 31 ? ~0u : (2u << s1) - 1u;
    return upTo & ~((1u << s0) - 1u);
}

// A plane a·x + b·y + c·z + d ≥ 0 in camera space.
struct Plane {
    glm::dvec4 p;
    bool outside(const glm::dvec3& c, double r) const {
        return glm::dot(glm::dvec3(p), c) + p.w < -r * glm::length(glm::dvec3(p));
    }
};

// Row r of a column-major glm matrix.
glm::dvec4 row(const glm::dmat4& m, int r) {
    return {m[0][r], m[1][r], m[2][r], m[3][r]};
}

// The camera-space point at NDC (x, y) and planar depth z.
glm::dvec3 unproject(const glm::dmat4& cameraToNDC, const glm::dmat4& ndcToCamera, double x,
                     double y, double z) {
    const glm::dvec4 clip = cameraToNDC * glm::dvec4(0.0, 0.0, -z, 1.0);
    const glm::dvec4 p = ndcToCamera * glm::dvec4(x, y, clip.z / clip.w, 1.0);
    return glm::dvec3(p) / p.w;
}

// Whether a spot light's cone (apex, unit axis, outer angle, range) misses a sphere: the
// sphere lies wholly outside the cone's side, beyond its range along the axis, or behind its
// apex.
bool coneMissesSphere(const glm::dvec3& apex, const glm::dvec3& axis, double sinAngle,
                      double cosAngle, double range, const glm::dvec3& centre, double radius) {
    const glm::dvec3 v = centre - apex;
    const double along = glm::dot(v, axis);
    const double across = std::sqrt(std::max(0.0, glm::dot(v, v) - along * along));
    // Distance from the sphere's centre to the cone's side, positive outside.
    const double toSide = cosAngle * across - sinAngle * along;
    return toSide > radius || along > range + radius || along < -radius;
}

// Squared distance from a point to a box (0 inside).
double distanceToBox2(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 d = glm::max(glm::max(lo - p, p - hi), glm::dvec3(0.0));
    return glm::dot(d, d);
}

// What the culling knows of the frame: its depths and size, the rows held, its tiles, the
// camera's projection and the rows of it the tiles' side planes are made of.
struct CullFrame {
    CullFrame(const DepthView& depth, const gbuffer::CameraInfo& camera, int width, int height,
              int tileSize, int rowBegin, int rowEnd)
        : depth(depth), width(width), height(height), tileSize(tileSize), rowBegin(rowBegin),
          rowEnd(rowEnd), cameraToNDC(camera.worldToNDC * glm::inverse(camera.worldToCamera)),
          ndcToCamera(glm::inverse(cameraToNDC)), r0(row(cameraToNDC, 0)), r1(row(cameraToNDC, 1)),
          r3(row(cameraToNDC, 3)) {}

    const DepthView& depth;
    int width, height, tileSize, rowBegin, rowEnd;
    glm::dmat4 cameraToNDC, ndcToCamera;
    glm::dvec4 r0, r1, r3;
};

// A tile's depth range over its surfaces (zmin > zmax: background only), and the slices of it
// that hold a pixel. Every sample of a deep G-buffer's pixels counts, as the surface of a flat
// one does.
struct TileDepths {
    float zmin, zmax;
    std::uint32_t pixelMask;
};

TileDepths tileDepths(const DepthView& depth, int x0, int x1, int y0, int y1) {
    float zmin = INFINITY, zmax = -INFINITY;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            for (int k = 0, n = depth.count(x, y); k < n; ++k) {
                const float z = depth.at(x, y, k);
                if (!std::isfinite(z)) continue;
                zmin = std::min(zmin, z);
                zmax = std::max(zmax, z);
            }
    TileDepths d{zmin, zmax, 0u};
    if (zmin > zmax) return d;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            for (int k = 0, n = depth.count(x, y); k < n; ++k) {
                const float z = depth.at(x, y, k);
                if (std::isfinite(z)) d.pixelMask |= 1u << sliceIndex(z, zmin, zmax);
            }
    return d;
}

// Stage 1 for tile (tx, ty): its depth range, which slices hold a pixel, and the bounds of its
// sub-frustum between those depths. (Tile is TileLightLists' own.)
template <class Tile>
void boundTile(Tile& t, const CullFrame& f, int tx, int ty) {
    const int x0 = tx * f.tileSize, x1 = std::min(f.width, x0 + f.tileSize);
    // The tile's rows that are held (a strip may cut a tile).
    const int y0 = std::max(ty * f.tileSize, f.rowBegin);
    const int y1 = std::min({f.height, ty * f.tileSize + f.tileSize, f.rowEnd});
    const TileDepths d = tileDepths(f.depth, x0, x1, y0, y1);
    if (d.zmin > d.zmax) return; // background only
    t.zmin = d.zmin;
    t.zmax = d.zmax;
    t.pixelMask = d.pixelMask;
    const double nx[2] = {2.0 * x0 / f.width - 1.0, 2.0 * x1 / f.width - 1.0};
    const double ny[2] = {1.0 - 2.0 * y1 / f.height, 1.0 - 2.0 * y0 / f.height};
    const double nz[2] = {double(d.zmin), double(d.zmax)};
    glm::dvec3 corners[8];
    t.boxMin = glm::dvec3(INFINITY);
    t.boxMax = glm::dvec3(-INFINITY);
    for (int i = 0; i < 8; ++i) {
        corners[i] =
            unproject(f.cameraToNDC, f.ndcToCamera, nx[i & 1], ny[(i >> 1) & 1], nz[i >> 2]);
        t.boxMin = glm::min(t.boxMin, corners[i]);
        t.boxMax = glm::max(t.boxMax, corners[i]);
    }
    // A little larger than exact: pixel positions are floats in the G-buffer.
    const glm::dvec3 margin = 1e-5 * (glm::abs(t.boxMin) + glm::abs(t.boxMax)) + 1e-6;
    t.boxMin -= margin;
    t.boxMax += margin;
    t.sphereCentre = 0.5 * (t.boxMin + t.boxMax);
    for (const glm::dvec3& c : corners)
        t.sphereRadius = std::max(t.sphereRadius, glm::length(c - t.sphereCentre));
    t.sphereRadius += glm::length(margin);
}

// A light's columns of tiles and, for a bounded one, its bound (and a spot's cone) in
// camera space.
struct Span {
    std::uint32_t light = 0;
    int tx0 = 0, tx1 = 0;
    bool bounded = false;
    glm::dvec3 centre{0.0}; // camera space
    double radius = 0.0;
    bool spot = false;
    glm::dvec3 apex{0.0}, axis{0.0}; // camera space
    double sinOuter = 0.0, cosOuter = 0.0, range = 0.0;
};

// Light i's span and its frame tile rows [ty0, ty1]; false where its bound is off screen.
bool lightSpan(const Light& light, size_t i, const gbuffer::CameraInfo& camera, const CullFrame& f,
               int tilesX, Span& span, int& ty0, int& ty1) {
    const bool bounded = light.isLocal() && std::isfinite(light.range);
    span = Span{};
    span.light = std::uint32_t(i);
    span.tx1 = tilesX - 1;
    span.bounded = bounded;
    if (bounded && light.type == LightType::Spot) {
        span.spot = true;
        span.apex = glm::dvec3(camera.worldToCamera * glm::dvec4(glm::dvec3(light.position), 1.0));
        span.axis = glm::normalize(
            glm::dvec3(camera.worldToCamera * glm::dvec4(glm::dvec3(light.direction), 0.0)));
        span.sinOuter = std::sin(double(light.outerConeAngle));
        span.cosOuter = std::cos(double(light.outerConeAngle));
        span.range = double(light.range) * (1.0 + 1e-4) + 1e-6;
    }
    ty0 = 0;
    ty1 = (f.height - 1) / f.tileSize; // frame tile rows
    if (!bounded) return true;
    const LightBound b = lightBound(light);
    // A little wider than the bound: the G-buffer's positions and depths are floats.
    span.radius = double(b.radius) * (1.0 + 1e-4) + 1e-6;
    span.centre = glm::dvec3(camera.worldToCamera * glm::dvec4(glm::dvec3(b.centre), 1.0));
    const PixelRect r = sphereScreenRect(glm::dvec3(b.centre), span.radius, camera.worldToCamera,
                                         f.cameraToNDC, f.width, f.height);
    if (r.empty()) return false;
    span.tx0 = r.x0 / f.tileSize;
    span.tx1 = (r.x1 - 1) / f.tileSize;
    ty0 = r.y0 / f.tileSize;
    ty1 = (r.y1 - 1) / f.tileSize;
    return true;
}

// Stage 2: each light's span, bucketed by the held tile rows [firstRow, lastRow] in light
// order.
std::vector<std::vector<Span>> spansByTileRow(const std::vector<Light>& lights,
                                              const gbuffer::CameraInfo& camera, const CullFrame& f,
                                              int tilesX, int firstRow, int lastRow) {
    std::vector<std::vector<Span>> rows(static_cast<size_t>(std::max(lastRow - firstRow + 1, 0)));
    for (size_t i = 0; i < lights.size(); ++i) {
        Span span;
        int ty0, ty1;
        if (!lightSpan(lights[i], i, camera, f, tilesX, span, ty0, ty1)) continue;
        for (int ty = std::max(ty0, firstRow); ty <= std::min(ty1, lastRow); ++ty)
            rows[size_t(ty - firstRow)].push_back(span);
    }
    return rows;
}

// Stage 3 for a bounded light's span and tile tx of a row between the planes `below` and
// `above`: the tile's two other side planes, its box and sphere, then the depth slices the
// light's bound overlaps among those that hold a pixel (0: none).
template <class Tile>
std::uint32_t sliceMask(const Span& s, const Tile& t, int tx, const Plane& below,
                        const Plane& above, const CullFrame& f) {
    const double near = -s.centre.z - s.radius, far = -s.centre.z + s.radius;
    if (far < t.zmin || near > t.zmax) return 0;
    const double xLeft = 2.0 * double(tx * f.tileSize) / f.width - 1.0;
    const double xRight = 2.0 * double(std::min(f.width, (tx + 1) * f.tileSize)) / f.width - 1.0;
    const Plane left{f.r0 - xLeft * f.r3}, right{xRight * f.r3 - f.r0};
    if (left.outside(s.centre, s.radius) || right.outside(s.centre, s.radius) ||
        below.outside(s.centre, s.radius) || above.outside(s.centre, s.radius))
        return 0;
    if (distanceToBox2(s.centre, t.boxMin, t.boxMax) > s.radius * s.radius) return 0;
    if (s.spot && coneMissesSphere(s.apex, s.axis, s.sinOuter, s.cosOuter, s.range, t.sphereCentre,
                                   t.sphereRadius))
        return 0;
    const int s0 = sliceIndex(float(std::max(near, double(t.zmin))), t.zmin, t.zmax);
    const int s1 = sliceIndex(float(std::min(far, double(t.zmax))), t.zmin, t.zmax);
    return sliceRange(s0, s1) & t.pixelMask;
}

// Stage 3 for frame tile row ty (`tiles`, its first): each span's entries in its tiles.
template <class Tile>
void listRow(Tile* tiles, const std::vector<Span>& spans, int64_t ty, const CullFrame& f) {
    // NDC y grows upwards, pixel rows downwards.
    const double yTop = 1.0 - 2.0 * double(ty * f.tileSize) / f.height;
    const double yBottom =
        1.0 - 2.0 * double(std::min<int64_t>(f.height, (ty + 1) * f.tileSize)) / f.height;
    const Plane below{f.r1 - yBottom * f.r3}, above{yTop * f.r3 - f.r1};
    for (const Span& s : spans) {
        for (int tx = s.tx0; tx <= s.tx1; ++tx) {
            Tile& t = tiles[tx];
            if (t.pixelMask == 0) continue;
            if (!s.bounded) {
                t.entries.push_back({s.light, ~0u});
                continue;
            }
            const std::uint32_t mask = sliceMask(s, t, tx, below, above, f);
            if (mask) t.entries.push_back({s.light, mask});
        }
    }
}

} // namespace

std::uint32_t TileLightLists::sliceBit(int x, int y, float z) const {
    if (!std::isfinite(z)) return ~0u; // not a surface the lists were built for
    const Tile& t = m_tiles[tileIndex(x, y)];
    return 1u << sliceIndex(z, t.zmin, t.zmax);
}

size_t TileLightLists::totalEntries() const {
    size_t n = 0;
    for (const Tile& t : m_tiles)
        n += t.entries.size();
    return n;
}

void TileLightLists::build(const std::vector<Light>& lights, const gbuffer::CameraInfo& camera,
                           const DepthView& depth, int width, int height, int tileSize,
                           int nthreads, int rowBegin, int rowEnd) {
    rowBegin = std::clamp(rowBegin, 0, height);
    rowEnd = rowEnd < 0 ? height : std::clamp(rowEnd, rowBegin, height);
    m_tileSize = tileSize;
    m_tilesX = (width + tileSize - 1) / tileSize;
    m_firstTileRow = rowBegin / tileSize;
    const int lastTileRow = rowEnd > rowBegin ? (rowEnd - 1) / tileSize : m_firstTileRow - 1;
    m_tilesY = lastTileRow - m_firstTileRow + 1;
    m_tiles.assign(size_t(m_tilesX) * size_t(std::max(m_tilesY, 0)), Tile{});

    const CullFrame f(depth, camera, width, height, tileSize, rowBegin, rowEnd);

    // 1. Each tile's depth range, occupied slices and sub-frustum bounds.
    OIIO::parallel_for(
        0, m_tilesY,
        [&](int64_t local) {
            for (int tx = 0; tx < m_tilesX; ++tx)
                boundTile(m_tiles[size_t(local) * size_t(m_tilesX) + size_t(tx)], f, tx,
                          m_firstTileRow + int(local));
        },
        perItem(nthreads));
    // 2. Each light's screen rectangle, bucketed by tile row in light order.
    const std::vector<std::vector<Span>> rows =
        spansByTileRow(lights, camera, f, m_tilesX, m_firstTileRow, lastTileRow);
    // 3. Per tile: the sub-frustum's four side planes, then the depth slices.
    OIIO::parallel_for(
        0, m_tilesY,
        [&](int64_t local) {
            listRow(&m_tiles[size_t(local) * size_t(m_tilesX)], rows[size_t(local)],
                    m_firstTileRow + local, f);
        },
        perItem(nthreads));
}

} // namespace dhdr
