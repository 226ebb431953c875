#include "denoise/denoise_buffers.h"
#include "denoise/denoise_lanes.h"
#include "denoise/simd_lanes.h"

#include <algorithm>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/core/cpu_features.h>
#include <dhdr/deferred/denoise/denoise.h>
#include <optional>

// The kernels below hold 32-byte vectors in always-inlined helpers (simd_lanes.h).
#pragma GCC diagnostic ignored "-Wpsabi"

namespace dhdr {

namespace {

using simd::any;
using simd::expNegative;
using simd::load;
using simd::Mask;
using simd::select;
using simd::splat;
using simd::store;

// The B-spline of the filter's taps (1/4, 1/2, 1/4): 3 × 3 taps a pass.
constexpr int kRadius = kDenoiseRadius;
constexpr float kKernel[2 * kRadius + 1] = {1.0f / 4, 1.0f / 2, 1.0f / 4};
// SVGF's σ_l: how many standard deviations of the estimate a difference may be and still mix.
constexpr float kSignalSigma = 4.0f;
constexpr int kMaxLanes = kDenoiseMaxLanes;
// Pixel p's side of the guide's weight, for W pixels of a row.
template <int W>
struct GuideCentre {
    using F = typename simd::Lanes<W>::F;
    F px, py, pz, nx, ny, nz, object;
    [[gnu::always_inline]] GuideCentre(const Guide& g, int y, int x)
        : px(load<W>(g.px.row(y) + x)), py(load<W>(g.py.row(y) + x)), pz(load<W>(g.pz.row(y) + x)),
          nx(load<W>(g.nx.row(y) + x)), ny(load<W>(g.ny.row(y) + x)), nz(load<W>(g.nz.row(y) + x)),
          object(load<W>(g.object.row(y) + x)) {}
};

// The guide's weight of taps q for pixels p (q ≠ p): normals' agreement max(0, n_p·n_q)^64,
// distance off p's tangent plane exp(−(n_p·d)² / (0.05 |d|)²), the same object.
template <int W>
DHDR_LANES_INLINE typename simd::Lanes<W>::F geometryWeight(const Guide& g, const GuideCentre<W>& c,
                                                            int qy, int qx) {
    using F = typename simd::Lanes<W>::F;
    const F facing = simd::max<F>(splat<F>(0.0f), c.nx * load<W>(g.nx.row(qy) + qx) +
                                                      c.ny * load<W>(g.ny.row(qy) + qx) +
                                                      c.nz * load<W>(g.nz.row(qy) + qx));
    F f = facing * facing; // facing^64 by squaring
    for (int k = 0; k < 5; ++k)
        f = f * f;
    const F dx = load<W>(g.px.row(qy) + qx) - c.px, dy = load<W>(g.py.row(qy) + qx) - c.py,
            dz = load<W>(g.pz.row(qy) + qx) - c.pz;
    const F d2 = dx * dx + dy * dy + dz * dz;
    const F along = c.nx * dx + c.ny * dy + c.nz * dz;
    const Mask<F> apart = d2 > splat<F>(0.0f);
    const F off = along * along / select<F>(apart, splat<F>(0.0025f) * d2, splat<F>(1.0f));
    const F weight = f * select<F>(apart, expNegative<F>(splat<F>(0.0f) - off), splat<F>(1.0f));
    const Mask<F> keep = (load<W>(g.surface.row(qy) + qx) > splat<F>(0.0f)) &
                         (load<W>(g.object.row(qy) + qx) == c.object);
    return select<F>(keep, weight, splat<F>(0.0f));
}

} // namespace

// Where an estimate is unsettled (outside the anonymous namespace: denoise_buffers.h names
// it). It is settled where it says nothing is there to filter: a
// pair whose shadowed and unshadowed sums are equal (nothing blocked: ratio 1), or a single
// value of 0. A pass over a neighbourhood that is settled everywhere gives exactly that ratio
// or value again (every tap adds equal sums, or zeros), so each pass is computed only within
// the reach, through the passes still to come, of an unsettled pixel: the result is the same
// bits as filtering everywhere, the pairs' ratios and the single values.
class Unsettled {
public:
    Unsettled(const DenoiseEstimate& e, const DenoiseGuide& g) : m_w(g.width), m_h(g.height) {
        const size_t n = size_t(m_w) * size_t(m_h);
        const std::vector<float>& v = *e.planes;
        m_table.assign(size_t(m_w + 1) * size_t(m_h + 1), 0);
        for (int y = 0; y < m_h; ++y) {
            int row = 0;
            for (int x = 0; x < m_w; ++x) {
                const size_t i = size_t(y) * size_t(m_w) + size_t(x);
                row += g.surface[i] && (e.count == 2 ? v[i] != v[n + i] : v[i] != 0.0f);
                at(y + 1, x + 1) = at(y, x + 1) + row;
            }
        }
    }

    // Row y's unsettled pixels within r rows, counted by column up to each x, shifted so that
    // pixel x has an unsettled one within r rows and columns when counts[x + 2r + 1] −
    // counts[x] > 0 (x in [0, width rounded up to the lanes)).
    void rowCounts(int y, int r, std::vector<std::int32_t>& counts) const {
        const int y0 = std::max(y - r, 0), y1 = std::min(y + r + 1, m_h);
        counts.resize(size_t(m_w + 2 * r + kMaxLanes + 1));
        for (size_t i = 0; i < counts.size(); ++i) {
            const int x = std::clamp(int(i) - r, 0, m_w);
            counts[i] = at(y1, x) - at(y0, x);
        }
    }

private:
    int& at(int y, int x) { return m_table[size_t(y) * size_t(m_w + 1) + size_t(x)]; }
    int at(int y, int x) const { return m_table[size_t(y) * size_t(m_w + 1) + size_t(x)]; }
    int m_w, m_h;
    std::vector<int> m_table; // summed-area table of the unsettled pixels
};

namespace {

// How far from an unsettled pixel pass `pass` must be computed: the reach of the passes after
// it (their taps read this pass's results) plus the final result's reach; the variance
// estimate (pass −1) two pixels further.
constexpr int reachBefore(int pass) {
    int r = kDenoiseReach;
    for (int later = pass + 1; later < kDenoiseIterations; ++later)
        r += kRadius << later;
    return r;
}

// Per row: the unsettled counts of each estimate that skips settled pixels (Unsettled).
struct RowCounts {
    std::vector<std::vector<std::int32_t>> counts;
    RowCounts(const std::vector<EstimateState>& state, int y, int pass) : counts(state.size()) {
        for (size_t e = 0; e < state.size(); ++e)
            if (state[e].unsettled) state[e].unsettled->rowCounts(y, reachBefore(pass), counts[e]);
    }
};

// Per estimate, the lanes of pixels (y, x…x+W−1) it is filtered at, and whether any: a
// surface, where the estimate exists, near an unsettled pixel. Whether any lane of any estimate.
template <int W, class M>
DHDR_LANES_INLINE bool liveLanes(const std::vector<EstimateState>& state, const RowCounts& rows,
                                 const M& surface, int y, int x, int pass, simd::Array<M>& live,
                                 std::vector<char>& anyLive) {
    using F = typename simd::Lanes<W>::F;
    bool anyEstimate = false;
    for (size_t e = 0; e < state.size(); ++e) {
        M lanes = state[e].active
                      ? surface & (load<W>(state[e].active->row(y) + x) > splat<F>(0.0f))
                      : surface;
        if (state[e].unsettled && any(lanes)) {
            const std::int32_t* counts = rows.counts[e].data() + x;
            lanes &= simd::load<W>(counts + 2 * reachBefore(pass) + 1) - simd::load<W>(counts) > 0;
        }
        live.set(e, lanes);
        anyLive[e] = any(lanes);
        anyEstimate = anyEstimate || anyLive[e];
    }
    return anyEstimate;
}

// A lobe's direction: exp(−(1 − d_p·d_q) / σ_p²) for pixels p = (y, x…x+W−1), taps q.
template <int W>
DHDR_LANES_INLINE typename simd::Lanes<W>::F lobeWeight(const EstimateState& s, int y, int x,
                                                        int qy, int qx) {
    using F = typename simd::Lanes<W>::F;
    F dot = splat<F>(0.0f);
    for (int k = 0; k < 3; ++k)
        dot += load<W>(s.direction[k]->row(y) + x) * load<W>(s.direction[k]->row(qy) + qx);
    const F width = load<W>(s.width->row(y) + x);
    return expNegative<F>(splat<F>(0.0f) -
                          simd::max<F>(splat<F>(1.0f) - dot, splat<F>(0.0f)) / (width * width));
}

// What a pass reads and writes: the previous pass's state, the next one's.
struct Pass {
    const Guide& guide;
    const std::vector<DenoiseEstimate>& estimates;
    std::vector<EstimateState>& state;
    std::vector<EstimateState>& next;
    // Per estimate, per kMaxLanes pixels of a row: whether a pass has filtered any of them so
    // far. Elsewhere both buffers hold the input (and a variance of 0) throughout, and the
    // passes store nothing.
    std::vector<std::vector<char>>& touched;
    int groupsPerRow;
};

// The variance per pixel from the 5 × 5 neighbourhood of the same surface (SVGF's spatial
// estimate where no history is), row y; each tap's geometry weight serves every estimate, and
// each estimate's sums stay in registers over its taps.
template <int W>
DHDR_LANES_INLINE void varianceRow(const Pass& p, int y) {
    using F = typename simd::Lanes<W>::F;
    using M = Mask<F>;
    constexpr int kTaps = 25;
    const Guide& guide = p.guide;
    std::vector<EstimateState>& state = p.state;
    const size_t m = state.size();
    simd::Array<M> live(m);
    std::vector<char> anyLive(m);
    const RowCounts counts(state, y, -1);
    for (int x = 0; x < guide.width; x += W) {
        const GuideCentre<W> centre(guide, y, x);
        const M surface = load<W>(guide.surface.row(y) + x) > splat<F>(0.0f);
        if (!liveLanes<W>(state, counts, surface, y, x, -1, live, anyLive)) continue;
        F wq[kTaps];
        int tapRow[kTaps], tapColumn[kTaps], taps = 0;
        F weights = splat<F>(0.0f);
        for (int j = -2; j <= 2; ++j) {
            const int qy = y + j;
            if (qy < 0 || qy >= guide.height) continue;
            for (int i = -2; i <= 2; ++i, ++taps) {
                wq[taps] = i == 0 && j == 0 ? select<F>(surface, splat<F>(1.0f), splat<F>(0.0f))
                                            : geometryWeight<W>(guide, centre, qy, x + i);
                tapRow[taps] = qy;
                tapColumn[taps] = x + i;
                weights += wq[taps];
            }
        }
        const F safe = select<F>(surface, weights, splat<F>(1.0f));
        for (size_t e = 0; e < m; ++e) {
            if (!anyLive[e]) continue;
            F s = splat<F>(0.0f), s2 = splat<F>(0.0f);
            for (int t = 0; t < taps; ++t) {
                const F v = load<W>(state[e].signal.row(tapRow[t]) + tapColumn[t]);
                s += wq[t] * v;
                s2 += wq[t] * v * v;
            }
            const F mean = s / safe;
            const F v = simd::max<F>(splat<F>(0.0f), s2 / safe - mean * mean);
            // In both buffers: a pixel the passes leave alone is read from either.
            store(select<F>(live[e], v, splat<F>(0.0f)), state[e].variance.row(y) + x);
            store(select<F>(live[e], v, splat<F>(0.0f)), p.next[e].variance.row(y) + x);
        }
    }
}

// One pass of the filter with holes of 2^pass pixels, row y. The taps' geometry weights are
// computed once for every estimate; each estimate's sums stay in registers over its taps.
template <int W>
DHDR_LANES_INLINE void filterRow(const Pass& p, int y, int pass) {
    using F = typename simd::Lanes<W>::F;
    using M = Mask<F>;
    constexpr int kTaps = (2 * kRadius + 1) * (2 * kRadius + 1);
    const Guide& guide = p.guide;
    const std::vector<EstimateState>& state = p.state;
    const size_t m = state.size();
    const int step = 1 << pass;
    simd::Array<M> live(m);
    std::vector<char> anyLive(m);
    const RowCounts counts(state, y, pass);
    for (int x = 0; x < guide.width; x += W) {
        const GuideCentre<W> c(guide, y, x);
        const M surface = load<W>(guide.surface.row(y) + x) > splat<F>(0.0f);
        const bool anyEstimate = liveLanes<W>(state, counts, surface, y, x, pass, live, anyLive);
        // The taps that reach a surface, in a fixed order (the same sums whatever the threads):
        // kernel × geometry weight, and where.
        F kernel[kTaps];
        int tapRow[kTaps], tapColumn[kTaps], taps = 0, centreTap = -1;
        for (int j = -kRadius; j <= kRadius && anyEstimate; ++j) {
            const int qy = y + j * step;
            if (qy < 0 || qy >= guide.height) continue;
            for (int i = -kRadius; i <= kRadius; ++i) {
                const int qx = x + i * step;
                const bool same = i == 0 && j == 0;
                const F geometry = same ? select<F>(surface, splat<F>(1.0f), splat<F>(0.0f))
                                        : geometryWeight<W>(guide, c, qy, qx);
                if (!any(geometry > splat<F>(0.0f))) continue;
                if (same) centreTap = taps;
                kernel[taps] = geometry * splat<F>(kKernel[i + kRadius] * kKernel[j + kRadius]);
                tapRow[taps] = qy;
                tapColumn[taps] = qx;
                ++taps;
            }
        }
        // The lobe weight of each tap, for the estimates guided by one lobe (they share it).
        F lobe[kTaps];
        const Planes* lobeOf = nullptr;
        // Its entry in `touched`, one per kMaxLanes pixels (on 4 lanes, two groups share one).
        const size_t group = size_t(y) * size_t(p.groupsPerRow) + size_t(x / kMaxLanes);
        for (size_t e = 0; e < m; ++e) {
            const EstimateState& s = state[e];
            EstimateState& o = p.next[e];
            if (anyLive[e]) p.touched[e][group] = 1;
            if (!p.touched[e][group]) continue;
            F weights = splat<F>(0.0f), var = splat<F>(0.0f), sum0 = splat<F>(0.0f),
              sum1 = splat<F>(0.0f);
            const bool single = p.estimates[e].count == 1;
            if (anyLive[e]) {
                const F centre = load<W>(s.signal.row(y) + x);
                const F inverseSpread =
                    splat<F>(1.0f) /
                    (splat<F>(kSignalSigma) * simd::sqrt<F>(load<W>(s.variance.row(y) + x)) +
                     splat<F>(1e-4f));
                if (s.width && s.width != lobeOf) {
                    for (int t = 0; t < taps; ++t)
                        if (t != centreTap)
                            lobe[t] = lobeWeight<W>(s, y, x, tapRow[t], tapColumn[t]);
                    lobeOf = s.width;
                }
                for (int t = 0; t < taps; ++t) {
                    const int qy = tapRow[t], qx = tapColumn[t];
                    const F signal = load<W>(s.signal.row(qy) + qx);
                    const F difference = simd::abs<F>(signal - centre);
                    F weight =
                        kernel[t] * expNegative<F>(splat<F>(0.0f) - difference * inverseSpread);
                    if (s.width && t != centreTap) weight = weight * lobe[t];
                    weights += weight;
                    var += weight * weight * load<W>(s.variance.row(qy) + qx);
                    // A single plane is its own signal, and has no second plane.
                    if (single) {
                        sum0 += weight * signal;
                        continue;
                    }
                    sum0 += weight * load<W>(s.plane[0].row(qy) + qx);
                    sum1 += weight * load<W>(s.plane[1].row(qy) + qx);
                }
            }
            // Pixels without a surface, or without the estimate, keep what they had.
            const M on = live[e];
            const F safe = select<F>(on, weights, splat<F>(1.0f));
            store(select<F>(on, var / (safe * safe), load<W>(s.variance.row(y) + x)),
                  o.variance.row(y) + x);
            const F a = select<F>(on, sum0 / safe, load<W>(s.plane[0].row(y) + x));
            store(a, o.plane[0].row(y) + x);
            if (single) { // the second plane stays 0
                store(a, o.signal.row(y) + x);
                continue;
            }
            const F b = select<F>(on, sum1 / safe, load<W>(s.plane[1].row(y) + x));
            store(b, o.plane[1].row(y) + x);
            store(select<F>(b > splat<F>(0.0f), a / b, splat<F>(1.0f)), o.signal.row(y) + x);
        }
    }
}

// A row of a pass (pass −1: the variance estimate), W pixels at a time.
void row4(const Pass& p, int y, int pass) {
    if (pass < 0)
        varianceRow<4>(p, y);
    else
        filterRow<4>(p, y, pass);
}

#if defined(__x86_64__)
[[gnu::target("avx2")]] void row8(const Pass& p, int y, int pass) {
    if (pass < 0)
        varianceRow<8>(p, y);
    else
        filterRow<8>(p, y, pass);
}
#endif

} // namespace

int atrousLanes() {
#if defined(__x86_64__)
    // Once: the CPU, and a kernel asked for in DHDR_EMBREE_ISA, do not change while running.
    static const int lanes = [] {
        if (!__builtin_cpu_supports("avx2")) return 4;
        const std::string isa = embreeIsaRequested();
        return isa.empty() || isa == "avx2" || isa == "avx512" ? 8 : 4;
    }();
    return lanes;
#else
    return 4;
#endif
}

float expNegative(float x) {
    using F = simd::Lanes<4>::F;
    return expNegative<F>(splat<F>(x))[0];
}

void atrousFilter(const std::vector<DenoiseEstimate>& estimates, const DenoiseGuide& dg,
                  int nthreads) {
    atrousFilterLanes(estimates, dg, nthreads, atrousLanes());
}

void atrousFilterLanes(const std::vector<DenoiseEstimate>& estimates, const DenoiseGuide& dg,
                       int nthreads, int lanes) {
    const int w = dg.width, h = dg.height;
    const size_t n = size_t(w) * size_t(h);
    if (n == 0) return;
    for (const DenoiseEstimate& e : estimates)
        if (!e.planes || (e.count != 1 && e.count != 2) || e.planes->size() < n * size_t(e.count) ||
            (e.direction && (!e.width || e.direction->size() < n || e.width->size() < n)) ||
            (e.active && e.active->size() < n))
            return;
    const size_t m = estimates.size();
    FilterBuffers buffers(estimates, dg, nthreads);
    const Guide& guide = buffers.guide;
    std::vector<EstimateState>&state = buffers.state, &next = buffers.next;
    std::vector<std::optional<Unsettled>> unsettled(m);
    for (size_t e = 0; e < m; ++e)
        if (estimates[e].skipSettled) {
            unsettled[e].emplace(estimates[e], dg);
            state[e].unsettled = next[e].unsettled = &*unsettled[e];
        }
    void (*row)(const Pass&, int, int) = row4;
#if defined(__x86_64__)
    if (lanes == 8 && __builtin_cpu_supports("avx2")) row = row8;
#endif
    const int firstRow = std::clamp(dg.firstRow, 0, h),
              endRow = dg.endRow < 0 ? h : std::clamp(dg.endRow, firstRow, h);
    const int groupsPerRow = (w + kMaxLanes - 1) / kMaxLanes;
    std::vector<std::vector<char>> touched(m, std::vector<char>(size_t(groupsPerRow) * size_t(h)));
    for (int pass = -1; pass < kDenoiseIterations; ++pass) {
        const Pass work{guide, estimates, state, next, touched, groupsPerRow};
        // The rows the later passes' taps read from this one.
        int reach = 0;
        for (int later = pass + 1; later < kDenoiseIterations; ++later)
            reach += kRadius << later;
        parallelRows(std::max(firstRow - reach, 0), std::min(endRow + reach, h), nthreads,
                     [&](int64_t y) { row(work, int(y), pass); });
        // The variance is estimated in place; every filter pass reads the previous one only.
        if (pass >= 0) state.swap(next);
    }
    parallelRows(firstRow, endRow, nthreads, [&](int64_t yy) {
        const int y = int(yy);
        for (size_t e = 0; e < m; ++e)
            for (int c = 0; c < estimates[e].count; ++c)
                std::copy_n(state[e].plane[c].row(y), w,
                            estimates[e].planes->data() + size_t(c) * n + size_t(y) * size_t(w));
    });
}

void atrousFilter(std::vector<float>& planes, int count, const DenoiseGuide& guide, int nthreads) {
    atrousFilter({DenoiseEstimate{&planes, count}}, guide, nthreads);
}

} // namespace dhdr
