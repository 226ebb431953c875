#include <OpenImageIO/parallel.h>
#include <OpenImageIO/simd.h>
#include <algorithm>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/denoise.h>
#include <optional>

namespace dhdr {

namespace {

using OIIO::simd::vbool4;
using OIIO::simd::vfloat4;
using OIIO::simd::vint4;

// The B-spline of the filter's taps (1/4, 1/2, 1/4): 3 × 3 taps a pass.
constexpr int kRadius = 1;
constexpr float kKernel[2 * kRadius + 1] = {1.0f / 4, 1.0f / 2, 1.0f / 4};
// SVGF's σ_l: how many standard deviations of the estimate a difference may be and still mix.
constexpr float kSignalSigma = 4.0f;
// The filter runs on four pixels of a row at once; rows are padded with pixels without a
// surface by the widest step's reach on either side, so that no tap needs a bounds check.
constexpr int kLanes = 4;
constexpr int kPad = std::max(2, kRadius << (kDenoiseIterations - 1));

// Cephes' expf on four lanes: x = z ln 2 + r with ln 2 in two parts (z ln 2 exact for the
// reduction), |r| ≤ ½ ln 2, e^r by its polynomial, times 2^z from the exponent bits. Plain
// SSE2 arithmetic without fused multiply-adds, so the same bits on every x86-64 CPU (libm's
// expf has FMA and non-FMA variants that may differ in the last bit).
OIIO_FORCEINLINE vfloat4 expNegative4(const vfloat4& x) {
    const vfloat4 inRange = max(x, vfloat4(-87.0f));
    const vfloat4 u = min(inRange, vfloat4(0.0f)) * vfloat4(1.44269504088896341f) + vfloat4(0.5f);
    vfloat4 z = vfloat4(vint4(u)); // truncation, then down to the floor for negative u
    z = select(z > u, z - vfloat4(1.0f), z);
    vfloat4 r = min(inRange, vfloat4(0.0f)) - z * vfloat4(0.693359375f);
    r = r - z * vfloat4(-2.12194440e-4f);
    vfloat4 p(1.9875691500e-4f);
    p = p * r + vfloat4(1.3981999507e-3f);
    p = p * r + vfloat4(8.3334519073e-3f);
    p = p * r + vfloat4(4.1665795894e-2f);
    p = p * r + vfloat4(1.6666665459e-1f);
    p = p * r + vfloat4(5.0000001201e-1f);
    p = p * (r * r) + r + vfloat4(1.0f);
    const vfloat4 scale = bitcast_to_float((vint4(z) + vint4(127)) << 23);
    return select(x > vfloat4(-87.0f), select(x < vfloat4(0.0f), p * scale, vfloat4(1.0f)),
                  vfloat4(0.0f));
}

// One plane of floats per quantity, rows padded (kPad each side, width rounded up to lanes).
struct Planes {
    int stride = 0;
    std::vector<float> values;
    float* row(int y) { return values.data() + size_t(y) * size_t(stride) + kPad; }
    const float* row(int y) const { return values.data() + size_t(y) * size_t(stride) + kPad; }
};

// The guide laid out for four lanes: positions, normals, object and surface as planes.
struct Guide {
    int width = 0, height = 0, stride = 0;
    Planes px, py, pz, nx, ny, nz, object, surface;
    explicit Guide(const DenoiseGuide& g) : width(g.width), height(g.height) {
        stride = kPad + (width + kLanes - 1) / kLanes * kLanes + kPad;
        for (Planes* p : {&px, &py, &pz, &nx, &ny, &nz, &object, &surface}) {
            p->stride = stride;
            p->values.assign(size_t(stride) * size_t(height), 0.0f);
        }
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const size_t i = size_t(y) * size_t(width) + size_t(x);
                px.row(y)[x] = g.position[i].x;
                py.row(y)[x] = g.position[i].y;
                pz.row(y)[x] = g.position[i].z;
                nx.row(y)[x] = g.normal[i].x;
                ny.row(y)[x] = g.normal[i].y;
                nz.row(y)[x] = g.normal[i].z;
                object.row(y)[x] = g.object[i];
                surface.row(y)[x] = g.surface[i] ? 1.0f : 0.0f;
            }
    }
};

// Pixel p's side of the guide's weight, for four pixels of a row.
struct GuideCentre {
    vfloat4 px, py, pz, nx, ny, nz, object;
    GuideCentre(const Guide& g, int y, int x)
        : px(g.px.row(y) + x), py(g.py.row(y) + x), pz(g.pz.row(y) + x), nx(g.nx.row(y) + x),
          ny(g.ny.row(y) + x), nz(g.nz.row(y) + x), object(g.object.row(y) + x) {}
};

// The guide's weight of taps q for pixels p (q ≠ p): normals' agreement max(0, n_p·n_q)^64,
// distance off p's tangent plane exp(−(n_p·d)² / (0.05 |d|)²), the same object.
OIIO_FORCEINLINE vfloat4 geometryWeight(const Guide& g, const GuideCentre& c, int qy, int qx) {
    const vfloat4 facing =
        max(vfloat4(0.0f), c.nx * vfloat4(g.nx.row(qy) + qx) + c.ny * vfloat4(g.ny.row(qy) + qx) +
                               c.nz * vfloat4(g.nz.row(qy) + qx));
    vfloat4 f = facing * facing; // facing^64 by squaring
    for (int k = 0; k < 5; ++k)
        f = f * f;
    const vfloat4 dx = vfloat4(g.px.row(qy) + qx) - c.px, dy = vfloat4(g.py.row(qy) + qx) - c.py,
                  dz = vfloat4(g.pz.row(qy) + qx) - c.pz;
    const vfloat4 d2 = dx * dx + dy * dy + dz * dz;
    const vfloat4 along = c.nx * dx + c.ny * dy + c.nz * dz;
    const vbool4 apart = d2 > vfloat4(0.0f);
    const vfloat4 off = along * along / select(apart, vfloat4(0.0025f) * d2, vfloat4(1.0f));
    const vfloat4 weight = f * select(apart, expNegative4(vfloat4(0.0f) - off), vfloat4(1.0f));
    const vbool4 keep = (vfloat4(g.surface.row(qy) + qx) > vfloat4(0.0f)) &
                        (vfloat4(g.object.row(qy) + qx) == c.object);
    return select(keep, weight, vfloat4(0.0f));
}

// Where an estimate is unsettled. It is settled where it says nothing is there to filter: a
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

    // Whether an unsettled pixel lies within r rows and columns of (x + l, y), per lane l.
    vbool4 near(int y, int x, int r) const {
        const int y0 = std::max(y - r, 0), y1 = std::min(y + r + 1, m_h);
        int lanes[kLanes];
        for (int l = 0; l < kLanes; ++l) {
            const int x0 = std::clamp(x + l - r, 0, m_w), x1 = std::clamp(x + l + r + 1, 0, m_w);
            lanes[l] = at(y1, x1) - at(y0, x1) - at(y1, x0) + at(y0, x0) > 0 ? -1 : 0;
        }
        return vbool4(lanes[0], lanes[1], lanes[2], lanes[3]);
    }

private:
    int& at(int y, int x) { return m_table[size_t(y) * size_t(m_w + 1) + size_t(x)]; }
    int at(int y, int x) const { return m_table[size_t(y) * size_t(m_w + 1) + size_t(x)]; }
    int m_w, m_h;
    std::vector<int> m_table; // summed-area table of the unsettled pixels
};

// How far from an unsettled pixel pass `pass` must be computed: the reach of the passes after
// it (their taps read this pass's results) plus the final result's reach; the variance
// estimate (pass −1) two pixels further.
constexpr int reachBefore(int pass) {
    int r = kDenoiseReach;
    for (int later = pass + 1; later < kDenoiseIterations; ++later)
        r += kRadius << later;
    return r;
}

// Per estimate: its signal (the ratio of a pair of planes, shadowed over unshadowed light, 1
// where nothing was seen; or the one plane's value), its variance and its planes.
struct EstimateState {
    Planes signal, variance, plane[2];
    const Planes* direction[3] = {nullptr, nullptr, nullptr};
    const Planes* width = nullptr;
    const Planes* active = nullptr; // 1 where the estimate exists; null: wherever a surface is
    const Unsettled* unsettled = nullptr; // null: filtered wherever it exists
};

void newPlanes(Planes& p, const Guide& g) {
    p.stride = g.stride;
    p.values.assign(size_t(g.stride) * size_t(g.height), 0.0f);
}

// Per estimate, the lanes of pixels (y, x…x+3) it is filtered at: a surface, and where it
// exists; whether any lane of any estimate is.
bool liveLanes(const std::vector<EstimateState>& state, const vbool4& surface, int y, int x,
               int pass, std::vector<vbool4>& live) {
    bool any = false;
    for (size_t e = 0; e < state.size(); ++e) {
        live[e] = state[e].active ? surface & (vfloat4(state[e].active->row(y) + x) > vfloat4(0.0f))
                                  : surface;
        if (state[e].unsettled && OIIO::simd::any(live[e]))
            live[e] &= state[e].unsettled->near(y, x, reachBefore(pass));
        any = any || OIIO::simd::any(live[e]);
    }
    return any;
}

// A lobe's direction: exp(−(1 − d_p·d_q) / σ_p²) for pixels p = (y, x…x+3), taps q.
OIIO_FORCEINLINE vfloat4 lobeWeight(const EstimateState& s, int y, int x, int qy, int qx) {
    vfloat4 dot(0.0f);
    for (int k = 0; k < 3; ++k)
        dot += vfloat4(s.direction[k]->row(y) + x) * vfloat4(s.direction[k]->row(qy) + qx);
    const vfloat4 width(s.width->row(y) + x);
    return expNegative4(vfloat4(0.0f) - max(vfloat4(1.0f) - dot, vfloat4(0.0f)) / (width * width));
}

float signalOf(float shadowed, float total, int count) {
    if (count == 2) return total > 0.0f ? shadowed / total : 1.0f;
    return shadowed;
}

} // namespace

float expNegative(float x) {
    float lanes[kLanes];
    expNegative4(vfloat4(x)).store(lanes);
    return lanes[0];
}

void atrousFilter(const std::vector<DenoiseEstimate>& estimates, const DenoiseGuide& dg,
                  int nthreads) {
    const int w = dg.width, h = dg.height;
    const size_t n = size_t(w) * size_t(h);
    if (n == 0) return;
    for (const DenoiseEstimate& e : estimates)
        if (!e.planes || (e.count != 1 && e.count != 2) || e.planes->size() < n * size_t(e.count) ||
            (e.direction && (!e.width || e.direction->size() < n || e.width->size() < n)) ||
            (e.active && e.active->size() < n))
            return;
    const size_t m = estimates.size();
    const Guide guide(dg);
    // Directions and widths of the estimates that have them, padded like the guide.
    std::vector<Planes> lobes;
    lobes.reserve(5 * m);
    std::vector<EstimateState> state(m), next(m);
    std::vector<std::optional<Unsettled>> unsettled(m);
    for (size_t e = 0; e < m; ++e) {
        const DenoiseEstimate& in = estimates[e];
        if (in.skipSettled) {
            unsettled[e].emplace(in, dg);
            state[e].unsettled = next[e].unsettled = &*unsettled[e];
        }
        for (EstimateState* s : {&state[e], &next[e]}) {
            newPlanes(s->signal, guide);
            newPlanes(s->variance, guide);
            newPlanes(s->plane[0], guide);
            newPlanes(s->plane[1], guide);
        }
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const size_t i = size_t(y) * size_t(w) + size_t(x);
                for (int c = 0; c < in.count; ++c)
                    state[e].plane[c].row(y)[x] = (*in.planes)[size_t(c) * n + i];
                state[e].signal.row(y)[x] =
                    signalOf(state[e].plane[0].row(y)[x], state[e].plane[1].row(y)[x], in.count);
            }
        if (in.active) {
            lobes.emplace_back();
            newPlanes(lobes.back(), guide);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    lobes.back().row(y)[x] =
                        (*in.active)[size_t(y) * size_t(w) + size_t(x)] ? 1.0f : 0.0f;
            state[e].active = next[e].active = &lobes.back();
        }
        if (!in.direction) continue;
        // Estimates guided by the same lobes share their planes, and so their lobe weight.
        const auto same = std::find_if(
            estimates.begin(), estimates.begin() + long(e), [&](const DenoiseEstimate& o) {
                return o.direction == in.direction && o.width == in.width;
            });
        if (same != estimates.begin() + long(e)) {
            const EstimateState& shared = state[size_t(same - estimates.begin())];
            for (EstimateState* s : {&state[e], &next[e]}) {
                std::copy(shared.direction, shared.direction + 3, s->direction);
                s->width = shared.width;
            }
            continue;
        }
        for (int k = 0; k < 4; ++k) {
            lobes.emplace_back();
            newPlanes(lobes.back(), guide);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const size_t i = size_t(y) * size_t(w) + size_t(x);
                    lobes.back().row(y)[x] = k < 3 ? (*in.direction)[i][k] : (*in.width)[i];
                }
            if (k < 3)
                state[e].direction[k] = next[e].direction[k] = &lobes.back();
            else
                state[e].width = next[e].width = &lobes.back();
        }
    }
    // The variance per pixel from the 5 × 5 neighbourhood of the same surface (SVGF's spatial
    // estimate where no history is); each tap's geometry weight serves every estimate.
    parallelRows(0, h, nthreads, [&](int64_t yy) {
        const int y = int(yy);
        std::vector<vfloat4> s(m), s2(m);
        std::vector<vbool4> live(m);
        for (int x = 0; x < w; x += kLanes) {
            const GuideCentre centre(guide, y, x);
            const vbool4 surface = vfloat4(guide.surface.row(y) + x) > vfloat4(0.0f);
            if (!liveLanes(state, surface, y, x, -1, live)) continue;
            std::fill(s.begin(), s.end(), vfloat4(0.0f));
            std::fill(s2.begin(), s2.end(), vfloat4(0.0f));
            vfloat4 weights(0.0f);
            for (int j = -2; j <= 2; ++j) {
                const int qy = y + j;
                if (qy < 0 || qy >= h) continue;
                for (int i = -2; i <= 2; ++i) {
                    const vfloat4 wq = i == 0 && j == 0
                                           ? select(surface, vfloat4(1.0f), vfloat4(0.0f))
                                           : geometryWeight(guide, centre, qy, x + i);
                    for (size_t e = 0; e < m; ++e) {
                        if (none(live[e])) continue;
                        const vfloat4 v(state[e].signal.row(qy) + x + i);
                        s[e] += wq * v;
                        s2[e] += wq * v * v;
                    }
                    weights += wq;
                }
            }
            const vfloat4 safe = select(surface, weights, vfloat4(1.0f));
            for (size_t e = 0; e < m; ++e) {
                if (none(live[e])) continue;
                const vfloat4 mean = s[e] / safe;
                const vfloat4 v = max(vfloat4(0.0f), s2[e] / safe - mean * mean);
                select(live[e], v, vfloat4(0.0f)).store(state[e].variance.row(y) + x);
            }
        }
    });
    for (int pass = 0; pass < kDenoiseIterations; ++pass) {
        const int step = 1 << pass;
        parallelRows(0, h, nthreads, [&](int64_t yy) {
            const int y = int(yy);
            std::vector<vfloat4> sum(2 * m), weights(m), var(m), inverseSpread(m), centre(m);
            std::vector<vbool4> live(m);
            for (int x = 0; x < w; x += kLanes) {
                const GuideCentre c(guide, y, x);
                const vbool4 surface = vfloat4(guide.surface.row(y) + x) > vfloat4(0.0f);
                const bool any = liveLanes(state, surface, y, x, pass, live);
                for (size_t e = 0; e < m; ++e) {
                    centre[e] = vfloat4(state[e].signal.row(y) + x);
                    inverseSpread[e] =
                        vfloat4(1.0f) /
                        (vfloat4(kSignalSigma) * sqrt(vfloat4(state[e].variance.row(y) + x)) +
                         vfloat4(1e-4f));
                }
                std::fill(sum.begin(), sum.end(), vfloat4(0.0f));
                std::fill(weights.begin(), weights.end(), vfloat4(0.0f));
                std::fill(var.begin(), var.end(), vfloat4(0.0f));
                if (any) {
                    // Taps in a fixed order: the same sums whatever the threads.
                    for (int j = -kRadius; j <= kRadius; ++j) {
                        const int qy = y + j * step;
                        if (qy < 0 || qy >= h) continue;
                        for (int i = -kRadius; i <= kRadius; ++i) {
                            const int qx = x + i * step;
                            const bool same = i == 0 && j == 0;
                            const vfloat4 geometry =
                                same ? select(surface, vfloat4(1.0f), vfloat4(0.0f))
                                     : geometryWeight(guide, c, qy, qx);
                            if (none(geometry > vfloat4(0.0f))) continue;
                            const vfloat4 kernel =
                                geometry * vfloat4(kKernel[i + kRadius] * kKernel[j + kRadius]);
                            const Planes* lobeOf = nullptr;
                            vfloat4 lobe(1.0f);
                            for (size_t e = 0; e < m; ++e) {
                                if (none(live[e])) continue;
                                const EstimateState& s = state[e];
                                const vfloat4 difference =
                                    abs(vfloat4(s.signal.row(qy) + qx) - centre[e]);
                                vfloat4 weight =
                                    kernel *
                                    expNegative4(vfloat4(0.0f) - difference * inverseSpread[e]);
                                if (s.width && !same) {
                                    if (s.width != lobeOf) {
                                        lobe = lobeWeight(s, y, x, qy, qx);
                                        lobeOf = s.width;
                                    }
                                    weight = weight * lobe;
                                }
                                weights[e] += weight;
                                var[e] += weight * weight * vfloat4(s.variance.row(qy) + qx);
                                sum[2 * e] += weight * vfloat4(s.plane[0].row(qy) + qx);
                                sum[2 * e + 1] += weight * vfloat4(s.plane[1].row(qy) + qx);
                            }
                        }
                    }
                }
                // Pixels without a surface, or without the estimate, keep what they had.
                for (size_t e = 0; e < m; ++e) {
                    const EstimateState& s = state[e];
                    EstimateState& o = next[e];
                    const vbool4 on = live[e];
                    const vfloat4 safe = select(on, weights[e], vfloat4(1.0f));
                    const vfloat4 a = select(on, sum[2 * e] / safe, vfloat4(s.plane[0].row(y) + x));
                    const vfloat4 b =
                        select(on, sum[2 * e + 1] / safe, vfloat4(s.plane[1].row(y) + x));
                    a.store(o.plane[0].row(y) + x);
                    b.store(o.plane[1].row(y) + x);
                    select(on, var[e] / (safe * safe), vfloat4(s.variance.row(y) + x))
                        .store(o.variance.row(y) + x);
                    for (int l = 0; l < kLanes; ++l)
                        o.signal.row(y)[x + l] = signalOf(
                            o.plane[0].row(y)[x + l], o.plane[1].row(y)[x + l], estimates[e].count);
                }
            }
        });
        state.swap(next);
    }
    for (size_t e = 0; e < m; ++e)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < estimates[e].count; ++c)
                    (*estimates[e].planes)[size_t(c) * n + size_t(y) * size_t(w) + size_t(x)] =
                        state[e].plane[c].row(y)[x];
}

void atrousFilter(std::vector<float>& planes, int count, const DenoiseGuide& guide, int nthreads) {
    atrousFilter({DenoiseEstimate{&planes, count}}, guide, nthreads);
}

} // namespace dhdr
