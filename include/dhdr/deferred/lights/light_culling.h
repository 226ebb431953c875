// Tiled light culling: for each screen tile, the lights that can reach any of its surfaces
// (seed: per-pixel light lists with per-light min/max depth).
#pragma once

#include <cstddef>
#include <cstdint>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/scene/lights.h>
#include <vector>

namespace dhdr {

// A sphere holding every point a local light can reach: its range sphere, or for a spot the
// smaller sphere around its cone.
struct LightBound {
    glm::vec3 centre{0.0f};
    float radius = 0.0f;
};
LightBound lightBound(const Light& light);

// Planar depth of a frame, or of a strip of its rows starting at `firstRow`, read in place
// (e.g. the Z channel of an interleaved G-buffer). Background pixels hold +∞ (or NaN).
// A deep G-buffer's depths: with `first` set, pixel p = (y − firstRow) · rowStride + x has
// the samples first[p] … first[p + 1] − 1, sample s's depth at data[s · pixelStride].
struct DepthView {
    const float* data = nullptr;
    size_t pixelStride = 1; // in floats
    size_t rowStride = 0;   // in floats; in pixels when `first` is set
    int firstRow = 0;       // the frame row that data's first row is
    const std::uint32_t* first = nullptr;

    int count(int x, int y) const {
        if (!first) return 1;
        const size_t p = size_t(y - firstRow) * rowStride + size_t(x);
        return int(first[p + 1] - first[p]);
    }
    float at(int x, int y, int k = 0) const {
        if (first) {
            const size_t p = size_t(y - firstRow) * rowStride + size_t(x);
            return data[(size_t(first[p]) + size_t(k)) * pixelStride];
        }
        return data[size_t(y - firstRow) * rowStride + size_t(x) * pixelStride];
    }
};

// The lights of each tile, in the order of the lights list. Each entry carries a 32-bit mask
// of the slices of the tile's depth range that the light's bound overlaps (2.5D culling,
// Harada 2012), so that a tile whose pixels lie at two depths, split by an edge, does not
// shade the far surfaces with the near lights: a pixel evaluates an entry only when the bit of
// its own depth slice is set.
class TileLightLists {
public:
    struct Entry {
        std::uint32_t light;
        std::uint32_t depthMask;
    };

    // Culls `lights` against the tiles of a width × height frame seen by `camera`. Lights
    // without a bound (directional, ambient, infinite range) are in every covered tile.
    // Only the tiles of frame rows [rowBegin, rowEnd) are built (rowEnd −1: to the bottom),
    // from the depths of those rows: a frame streamed strip by strip builds its lists a strip
    // at a time, and a pixel's list still holds every light that reaches it.
    void build(const std::vector<Light>& lights, const gbuffer::CameraInfo& camera,
               const DepthView& depth, int width, int height, int tileSize, int nthreads = 0,
               int rowBegin = 0, int rowEnd = -1);

    int tileSize() const { return m_tileSize; }
    // The entries of the tile holding pixel (x, y).
    const std::vector<Entry>& at(int x, int y) const { return m_tiles[tileIndex(x, y)].entries; }
    // The depth-slice bit of a pixel at depth z in the tile holding (x, y).
    std::uint32_t sliceBit(int x, int y, float z) const;
    // Entries summed over all tiles (for statistics and the benchmark).
    size_t totalEntries() const;

private:
    struct Tile {
        float zmin = 0.0f, zmax = 0.0f;
        std::uint32_t pixelMask = 0; // the slices holding at least one pixel; 0: no surface
        // The tile's sub-frustum between zmin and zmax, bounded in camera space by a box and
        // by a sphere.
        glm::dvec3 boxMin{0.0}, boxMax{0.0}, sphereCentre{0.0};
        double sphereRadius = 0.0;
        std::vector<Entry> entries;
    };
    size_t tileIndex(int x, int y) const {
        return size_t(y / m_tileSize - m_firstTileRow) * size_t(m_tilesX) + size_t(x / m_tileSize);
    }

    // m_tilesY rows of tiles are held, the first being frame tile row m_firstTileRow.
    int m_tileSize = 16, m_tilesX = 0, m_tilesY = 0, m_firstTileRow = 0;
    std::vector<Tile> m_tiles;
};

} // namespace dhdr
