#include "denoise/denoise_buffers.h"

#include <dhdr/common/parallel.h>

namespace dhdr {

namespace {

// An estimate's signal: the ratio of a pair, 1 where nothing was seen; a single plane's value.
// (The filter's rows compute the same in lanes.)
float signalOf(float shadowed, float total, int count) {
    if (count == 2) return total > 0.0f ? shadowed / total : 1.0f;
    return shadowed;
}

} // namespace

FilterBuffers::FilterBuffers(const std::vector<DenoiseEstimate>& estimates, const DenoiseGuide& dg,
                             int nthreads)
    : lobes(5 * estimates.size()), state(estimates.size()), next(estimates.size()) {
    const int w = dg.width, h = dg.height;
    const size_t n = size_t(w) * size_t(h), m = estimates.size();
    guide.width = w;
    guide.height = h;
    guide.stride = kDenoisePad + (w + kDenoiseMaxLanes - 1) / kDenoiseMaxLanes * kDenoiseMaxLanes +
                   kDenoisePad;
    for (Planes* p : {&guide.px, &guide.py, &guide.pz, &guide.nx, &guide.ny, &guide.nz,
                      &guide.object, &guide.surface})
        p->allocate(guide.stride, h);
    // The index in `lobes` of each estimate's mask and of its lobe's four planes (−1: none).
    std::vector<int> activeOf(m, -1), lobeOf(m, -1);
    size_t count = 0;
    for (size_t e = 0; e < m; ++e) {
        const DenoiseEstimate& in = estimates[e];
        for (EstimateState* s : {&state[e], &next[e]}) {
            s->signal.allocate(guide.stride, h);
            s->variance.allocate(guide.stride, h);
            s->plane[0].allocate(guide.stride, h);
            if (in.count == 2) s->plane[1].allocate(guide.stride, h);
        }
        if (in.active) {
            activeOf[e] = int(count);
            lobes[count].allocate(guide.stride, h);
            state[e].active = next[e].active = &lobes[count++];
        }
        if (!in.direction) continue;
        // Estimates guided by the same lobes share their planes, and so their lobe weight.
        const auto same = std::find_if(
            estimates.begin(), estimates.begin() + long(e), [&](const DenoiseEstimate& o) {
                return o.direction == in.direction && o.width == in.width;
            });
        size_t first = count;
        if (same != estimates.begin() + long(e)) {
            first = size_t(lobeOf[size_t(same - estimates.begin())]);
        } else {
            lobeOf[e] = int(count);
            for (int k = 0; k < 4; ++k)
                lobes[count++].allocate(guide.stride, h);
        }
        for (EstimateState* s : {&state[e], &next[e]}) {
            for (int k = 0; k < 3; ++k)
                s->direction[k] = &lobes[first + size_t(k)];
            s->width = &lobes[first + 3];
        }
    }
    // Every row of every plane, padding included.
    parallelRows(0, h, nthreads, [&](int64_t yy) {
        const int y = int(yy);
        const size_t row = size_t(y) * size_t(w);
        const glm::vec3* P = dg.position.data() + row;
        const glm::vec3* N = dg.normal.data() + row;
        guide.px.fill(y, w, [&](int x) { return P[x].x; });
        guide.py.fill(y, w, [&](int x) { return P[x].y; });
        guide.pz.fill(y, w, [&](int x) { return P[x].z; });
        guide.nx.fill(y, w, [&](int x) { return N[x].x; });
        guide.ny.fill(y, w, [&](int x) { return N[x].y; });
        guide.nz.fill(y, w, [&](int x) { return N[x].z; });
        guide.object.fill(y, w, [&](int x) { return dg.object[row + size_t(x)]; });
        guide.surface.fill(y, w, [&](int x) { return dg.surface[row + size_t(x)] ? 1.0f : 0.0f; });
        for (size_t e = 0; e < m; ++e) {
            const DenoiseEstimate& in = estimates[e];
            const float* values = in.planes->data() + row;
            // Both buffers: a pixel that no pass filters keeps its input in either.
            for (EstimateState* b : {&state[e], &next[e]}) {
                b->plane[0].fill(y, w, [&](int x) { return values[x]; });
                if (in.count == 2)
                    b->plane[1].fill(y, w, [&](int x) { return values[n + size_t(x)]; });
                b->signal.fill(y, w, [&](int x) {
                    return signalOf(values[x], in.count == 2 ? values[n + size_t(x)] : 0.0f,
                                    in.count);
                });
                b->variance.zero(y);
            }
            if (activeOf[e] >= 0)
                lobes[size_t(activeOf[e])].fill(
                    y, w, [&](int x) { return (*in.active)[row + size_t(x)] ? 1.0f : 0.0f; });
            if (lobeOf[e] < 0) continue;
            const size_t l = size_t(lobeOf[e]);
            for (int k = 0; k < 3; ++k)
                lobes[l + size_t(k)].fill(
                    y, w, [&](int x) { return (*in.direction)[row + size_t(x)][k]; });
            lobes[l + 3].fill(y, w, [&](int x) { return (*in.width)[row + size_t(x)]; });
        }
    });
}

} // namespace dhdr
