// The samples of a G-buffer as flat layers, for the denoiser: layer 0 holds each pixel's back
// opaque sample (a flat pixel's one sample), layers 1, 2, … its transparent samples front to
// back. A layer is then an image whose neighbouring pixels are the same kind of surface (the
// floor behind a pane and beside it are both in layer 0), and the filter runs on each alone.
// A pixel of several rays (GBufferView::severalRays) places the samples of one ray, its front
// sample's, in the layers; its other rays' samples are estimated by a neighbour's (donor).
#pragma once

#include <algorithm>
#include <cstdint>
#include <dhdr/deferred/gbuffer/shading_point.h>

namespace dhdr {

class SampleLayers {
public:
    // `coverage`: the G-buffer's coverage channel (gbuffer::Layout::coverage).
    SampleLayers(const GBufferView& view, int coverage) : m_view(view), m_coverage(coverage) {}

    // Whether sample k of pixel (x, y) has its own place in the layers: always, but in a pixel
    // of several rays only the samples along the ray of its front sample.
    bool own(int x, int y, int k) const {
        return !m_view.severalRays() || m_view.ray(x, y, k) == m_view.ray(x, y, 0);
    }
    // The layer of sample k of pixel (x, y): 0 for the opaque sample that ends its ray, else
    // 1 + its place among its ray's samples.
    int layer(int x, int y, int k) const {
        if (!m_view.deep()) return 0;
        if (!m_view.severalRays()) {
            const int n = m_view.samples(x, y);
            return k == n - 1 && opaque(x, y, k) ? 0 : k + 1;
        }
        const std::uint32_t ray = m_view.ray(x, y, k);
        int before = 0, after = 0;
        for (int j = 0; j < m_view.samples(x, y); ++j)
            (j < k ? before : after) += j != k && m_view.ray(x, y, j) == ray;
        return after == 0 && opaque(x, y, k) ? 0 : before + 1;
    }
    // How many layers pixel (x, y) reaches into: 1 + its own transparent samples (0 uncovered).
    int count(int x, int y) const {
        const int n = m_view.samples(x, y);
        if (n == 0 || !m_view.deep()) return n;
        int most = 0;
        for (int k = 0; k < n; ++k)
            if (own(x, y, k)) most = std::max(most, layer(x, y, k) + 1);
        return std::max(most, 1);
    }
    // The layers of the rows [ybegin, yend) of columns [xbegin, xend): at least 1.
    int count(int xbegin, int xend, int ybegin, int yend) const {
        int most = 1;
        if (m_view.deep())
            for (int y = ybegin; y < yend; ++y)
                for (int x = xbegin; x < xend; ++x)
                    most = std::max(most, count(x, y));
        return most;
    }

private:
    bool opaque(int x, int y, int k) const { return m_view.channels(x, y, k)[m_coverage] >= 1.0f; }

    const GBufferView& m_view;
    int m_coverage;
};

} // namespace dhdr
