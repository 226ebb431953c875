#include "environment/prefilter.h"

#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/core/sampling.h>

namespace dhdr {

namespace {

constexpr double kPiD = 3.14159265358979323846;

// The split sum's lobe about R (N = V = R): l weighted by D(h) / 4 · max(0, n·l), h the half
// vector of R and l; its integral over the sphere, E[max(0, n·l)] over GGX half vectors, by
// the midpoint rule in the variable u of Walter et al. 2007, eq. 35 (n·l depends on nothing
// else).
double ggxMeanCosine(double alpha) {
    const int n = 1 << 14;
    const double a2 = alpha * alpha;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double u = (double(i) + 0.5) / n;
        const double c2 = (1.0 - u) / (1.0 + (a2 - 1.0) * u);
        sum += std::max(0.0, 2.0 * c2 - 1.0);
    }
    return sum / n;
}

// Texels brighter than kBrightCap × the sky's mean luminance (lamps, windows, a sun left in
// the sky) keep that much, in their own chroma, for the prefilter's quadrature; the rest of
// their radiance is integrated exactly, as points (as bench/prefilter_error.cpp's reference
// does): a quadrature over mips alone spreads a few very bright texels over its coarse cells
// and left night and studio 9–11 % off at the 95th percentile at roughness 0.2.
constexpr double kBrightCap = 20.0;

// The bright rest as points: cells of 2^shift × 2^shift texels, each a point at the
// luminance-weighted mean direction of its bright texels carrying their summed radiance ×
// solid angle; structure of arrays.
struct BrightPoints {
    std::vector<float> x, y, z, r, g, b;
    size_t size() const { return x.size(); }
};

BrightPoints brightPoints(const std::vector<BrightTexel>& texels, const EnvironmentImage& sky,
                          int shift) {
    struct Cell {
        glm::dvec3 dir{0.0}, power{0.0};
    };
    std::vector<std::pair<std::int64_t, Cell>> cells; // sorted by key below
    std::vector<std::pair<std::int64_t, size_t>> keys(texels.size());
    for (size_t i = 0; i < texels.size(); ++i)
        keys[i] = {(std::int64_t(texels[i].y >> shift) << 32) | std::int64_t(texels[i].x >> shift),
                   i};
    std::sort(keys.begin(), keys.end());
    for (const auto& [key, i] : keys) {
        const BrightTexel& t = texels[i];
        if (cells.empty() || cells.back().first != key) cells.push_back({key, Cell{}});
        const double omega = sky.texelSolidAngle(t.y);
        const glm::vec3 d = equirectDirection(
            {(float(t.x) + 0.5f) / float(sky.width), (float(t.y) + 0.5f) / float(sky.height)});
        const double lum = (0.2126 * t.rest.r + 0.7152 * t.rest.g + 0.0722 * t.rest.b) * omega;
        cells.back().second.dir += glm::dvec3(d) * std::max(lum, 1e-30);
        cells.back().second.power += glm::dvec3(t.rest) * omega;
    }
    BrightPoints p;
    for (const auto& [key, c] : cells) {
        const glm::dvec3 d = glm::normalize(c.dir);
        p.x.push_back(float(d.x));
        p.y.push_back(float(d.y));
        p.z.push_back(float(d.z));
        p.r.push_back(float(c.power.r));
        p.g.push_back(float(c.power.g));
        p.b.push_back(float(c.power.b));
    }
    return p;
}

// Σ_j P_j D(h_j) / 4 · max(0, R·d_j): the bright points through the lobe about R (eight lanes
// of partial sums, in a fixed order).
glm::vec3 brightLobe(const BrightPoints& p, const glm::vec3& R, float alpha) {
    constexpr int kLanes = 8;
    const float a2 = alpha * alpha, a2m1 = 0.5f * (a2 - 1.0f);
    float ar[kLanes] = {}, ag[kLanes] = {}, ab[kLanes] = {};
    const size_t n = p.size();
    const float* __restrict px = p.x.data();
    const float* __restrict py = p.y.data();
    const float* __restrict pz = p.z.data();
    const float* __restrict pr = p.r.data();
    const float* __restrict pg = p.g.data();
    const float* __restrict pb = p.b.data();
    // (n·h)² = (1 + n·l) / 2: D ∝ 1 / ((n·h)² (α² − 1) + 1)².
    auto weight = [&](size_t j) {
        const float c = std::max(0.0f, R.x * px[j] + R.y * py[j] + R.z * pz[j]);
        const float den = (1.0f + c) * a2m1 + 1.0f;
        return c / (den * den);
    };
    size_t j = 0;
    for (; j + kLanes <= n; j += kLanes) {
        float w[kLanes];
        for (int l = 0; l < kLanes; ++l)
            w[l] = weight(j + size_t(l));
        for (int l = 0; l < kLanes; ++l) {
            ar[l] += w[l] * pr[j + size_t(l)];
            ag[l] += w[l] * pg[j + size_t(l)];
            ab[l] += w[l] * pb[j + size_t(l)];
        }
    }
    glm::vec3 sum(0.0f);
    for (; j < n; ++j)
        sum += weight(j) * glm::vec3(pr[j], pg[j], pb[j]);
    for (int l = 0; l < kLanes; ++l)
        sum += glm::vec3(ar[l], ag[l], ab[l]);
    return sum * (a2 / (4.0f * kPi));
}

// `env` resampled (bilinearly) to the power-of-two width nearest its own, 2:1; `env` itself
// when it is one. The prefilter's cells are texels of a mip chain split into their children,
// which downsampled() nests exactly only for even sizes (an odd width's last column is left out
// of the next mip): a 1000 × 500 sky was 2–3 % off.
EnvironmentImage powerOfTwo(EnvironmentImage env) {
    int w = 4;
    while (w * 2 <= env.width)
        w *= 2;
    if (double(env.width) / w > std::sqrt(2.0)) w *= 2;
    if (w == env.width && 2 * env.height == env.width) return env;
    EnvironmentImage out;
    out.width = w;
    out.height = w / 2;
    out.rgb.resize(size_t(out.width) * size_t(out.height) * 3);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            const glm::vec3 c = env.bilinear(
                {(float(x) + 0.5f) / float(out.width), (float(y) + 0.5f) / float(out.height)});
            float* p = &out.rgb[3 * (size_t(y) * size_t(out.width) + size_t(x))];
            p[0] = c.r;
            p[1] = c.g;
            p[2] = c.b;
        }
    return out;
}

// A cell of a row's quadrature: texel (x, y) of mip m, its normalized weight.
struct Cell {
    int m, y, x;
    float w;
};

// The cells of each row of a W-wide level, for the row's first texel: starting from the
// coarsest mip, a texel is split into its four children while it is wider than `cell` × (2α +
// its distance from R), so the cells are fine at the lobe's peak and coarse in its long tail;
// each cell is weighted by the lobe at its centre times its solid angle. Sorted, so that rows
// are summed in a fixed order. Rows are left empty once `cancel` (may be null) is set.
std::vector<std::vector<Cell>> quadratureCells(const std::vector<EnvironmentImage>& mips, int W,
                                               float alpha, double cell, int nthreads,
                                               const std::atomic<bool>* cancel) {
    const int H = W / 2, nm = int(mips.size());
    const double lambda = 2.0 * alpha, a2 = double(alpha) * alpha;
    // Per mip and texel row: the centre's cos θ and sin θ, the solid angle, and the cosine of
    // the distance from R within which a texel of the row is split: size > cell (λ + max(0,
    // dist − size)) holds never when size ≤ cell λ, else for dist < size / cell + size − λ.
    struct RowGeometry {
        double cosTheta, sinTheta, omega, cosSplit;
        bool split;
    };
    std::vector<std::vector<RowGeometry>> rows(static_cast<size_t>(nm));
    std::vector<std::vector<glm::dvec2>> columns(static_cast<size_t>(nm)); // cos φ, sin φ
    for (int m = 0; m < nm; ++m) {
        const EnvironmentImage& img = mips[size_t(m)];
        for (int ty = 0; ty < img.height; ++ty) {
            const double t0 = kPiD * ty / img.height, t1 = kPiD * (ty + 1) / img.height;
            const double sinMax =
                t0 <= 0.5 * kPiD && t1 >= 0.5 * kPiD ? 1.0 : std::max(std::sin(t0), std::sin(t1));
            const double size = std::max(t1 - t0, 2.0 * kPiD / img.width * sinMax);
            const bool split = m > 0 && size > cell * lambda;
            rows[size_t(m)].push_back(
                {std::cos(0.5 * (t0 + t1)), std::sin(0.5 * (t0 + t1)), img.texelSolidAngle(ty),
                 split ? std::cos(std::min(kPiD, size / cell + size - lambda)) : 2.0, split});
        }
        for (int tx = 0; tx < img.width; ++tx) {
            const double phi = 2.0 * kPiD * ((tx + 0.5) / img.width - 0.5);
            columns[size_t(m)].push_back({std::cos(phi), std::sin(phi)});
        }
    }

    // The cells of each row, for its first texel.
    std::vector<std::vector<Cell>> cells(static_cast<size_t>(H));
    OIIO::parallel_for(
        0, H,
        [&](int64_t y) {
            if (cancel && cancel->load(std::memory_order_relaxed)) return;
            const double theta = kPiD * (double(y) + 0.5) / H;
            const double phi = 2.0 * kPiD * (0.5 / W - 0.5);
            const glm::dvec3 R(std::sin(theta) * std::cos(phi), std::cos(theta),
                               std::sin(theta) * std::sin(phi));
            std::vector<Cell>& row = cells[size_t(y)];
            double sum = 0.0;
            auto visit = [&](auto&& self, int m, int tx, int ty) -> void {
                const RowGeometry& g = rows[size_t(m)][size_t(ty)];
                const glm::dvec2 c = columns[size_t(m)][size_t(tx)];
                const double cosd =
                    R.x * g.sinTheta * c.x + R.y * g.cosTheta + R.z * g.sinTheta * c.y;
                if (g.split && cosd > g.cosSplit) {
                    // The children downsampled() averaged into this texel (a last odd column
                    // or row of the finer mip goes with the last texel).
                    const EnvironmentImage& img = mips[size_t(m)];
                    const EnvironmentImage& fine = mips[size_t(m - 1)];
                    const int x1 = tx == img.width - 1 ? fine.width - 1 : 2 * tx + 1;
                    const int y1 = ty == img.height - 1 ? fine.height - 1 : 2 * ty + 1;
                    for (int cy = 2 * ty; cy <= y1; ++cy)
                        for (int cx = 2 * tx; cx <= x1; ++cx)
                            self(self, m - 1, cx, cy);
                    return;
                }
                if (!(cosd > 0.0)) return;
                const double den = 0.5 * (1.0 + cosd) * (a2 - 1.0) + 1.0;
                const double w = cosd / (den * den) * g.omega;
                row.push_back({m, ty, tx, float(w)});
                sum += w;
            };
            const EnvironmentImage& coarsest = mips.back();
            for (int ty = 0; ty < coarsest.height; ++ty)
                for (int tx = 0; tx < coarsest.width; ++tx)
                    visit(visit, nm - 1, tx, ty);
            const float norm = float(1.0 / std::max(sum, 1e-300));
            for (Cell& c : row)
                c.w *= norm;
            std::sort(row.begin(), row.end(), [](const Cell& a, const Cell& b) {
                return a.m != b.m ? a.m < b.m : a.y != b.y ? a.y < b.y : a.x < b.x;
            });
        },
        perItem(nthreads));
    return cells;
}

// The mips the cells read, rearranged so that texel x's read of a cell is at x + an
// offset, planar: a mip s = Wm / W times as wide as the level as s decimated copies of W
// columns (copy p: columns p, p + s, …); a mip r = W / Wm times narrower stretched to W
// columns (column j between its texels ⌊j / r⌋ and the next, (j mod r) / r of the way).
// Other widths are read directly (the generic path of accumulateRow).
struct Plane {
    enum Kind { Unused, Decimated, Stretched, Generic } kind = Unused;
    int factor = 1;
    std::vector<float> data; // [channel][copy][row][W]
};

std::vector<Plane> mipPlanes(const std::vector<EnvironmentImage>& mips,
                             const std::vector<std::vector<Cell>>& cells, int W, int nthreads) {
    const int nm = int(mips.size());
    std::vector<Plane> planes(static_cast<size_t>(nm));
    for (const std::vector<Cell>& row : cells)
        for (const Cell& c : row)
            planes[size_t(c.m)].kind = Plane::Generic;
    OIIO::parallel_for(
        0, nm,
        [&](int64_t m) {
            Plane& plane = planes[size_t(m)];
            if (plane.kind == Plane::Unused) return;
            const EnvironmentImage& img = mips[size_t(m)];
            const int wm = img.width, hm = img.height;
            if (wm >= W && wm % W == 0) {
                const int s = wm / W;
                plane.kind = Plane::Decimated;
                plane.factor = s;
                plane.data.resize(size_t(3) * size_t(s) * size_t(hm) * size_t(W));
                float* dst = plane.data.data();
                for (int ch = 0; ch < 3; ++ch)
                    for (int p = 0; p < s; ++p)
                        for (int ty = 0; ty < hm; ++ty) {
                            const float* src = &img.rgb[3 * size_t(ty) * size_t(wm)];
                            for (int q = 0; q < W; ++q)
                                *dst++ = src[3 * (size_t(p) + size_t(q) * size_t(s)) + size_t(ch)];
                        }
            } else if (wm < W && W % wm == 0) {
                const int r = W / wm;
                plane.kind = Plane::Stretched;
                plane.factor = r;
                plane.data.resize(size_t(3) * size_t(hm) * size_t(W));
                float* dst = plane.data.data();
                for (int ch = 0; ch < 3; ++ch)
                    for (int ty = 0; ty < hm; ++ty) {
                        const float* src = &img.rgb[3 * size_t(ty) * size_t(wm)];
                        for (int j = 0; j < W; ++j) {
                            const int i0 = j / r, i1 = i0 + 1 == wm ? 0 : i0 + 1;
                            const float f = float(j % r) / float(r);
                            *dst++ = (1.0f - f) * src[3 * size_t(i0) + size_t(ch)] +
                                     f * src[3 * size_t(i1) + size_t(ch)];
                        }
                    }
            }
        },
        perItem(nthreads));
    return planes;
}

// Σ over a row's cells of their weight × the radiance each texel of the row reads there, into
// `acc` (planar, 3 × W): the cells were found for the row's first texel; texel x reads them
// turned by x / W about the vertical axis.
void accumulateRow(const std::vector<Cell>& row, const std::vector<Plane>& planes,
                   const std::vector<EnvironmentImage>& mips, int W, float* acc) {
    // a[x] += w src[(offset + x) mod W]
    auto axpy = [W](float* __restrict a, const float* __restrict src, int offset, float w) {
        const int first = W - offset;
        for (int x = 0; x < first; ++x)
            a[x] += w * src[offset + x];
        for (int x = first; x < W; ++x)
            a[x] += w * src[offset + x - W];
    };
    for (const Cell& c : row) {
        const Plane& plane = planes[size_t(c.m)];
        const EnvironmentImage& img = mips[size_t(c.m)];
        const size_t hm = size_t(img.height), w = size_t(W);
        if (plane.kind == Plane::Decimated) {
            const int s = plane.factor, p = c.x % s;
            for (size_t ch = 0; ch < 3; ++ch)
                axpy(&acc[ch * w],
                     &plane.data[((ch * size_t(s) + size_t(p)) * hm + size_t(c.y)) * w], c.x / s,
                     c.w);
        } else if (plane.kind == Plane::Stretched) {
            for (size_t ch = 0; ch < 3; ++ch)
                axpy(&acc[ch * w], &plane.data[(ch * hm + size_t(c.y)) * w],
                     (c.x * plane.factor) % W, c.w);
        } else {
            // Texel x reads column c.x + ⌊x Wm / W⌋ and the next, frac(x Wm / W) between.
            const int wm = img.width;
            const float* src = &img.rgb[3 * size_t(c.y) * size_t(wm)];
            for (int x = 0; x < W; ++x) {
                const double px = double(x) * wm / W;
                const int ix = int(px);
                const float f = float(px - ix);
                const int i0 = (c.x + ix) % wm, i1 = i0 + 1 == wm ? 0 : i0 + 1;
                for (size_t ch = 0; ch < 3; ++ch)
                    acc[ch * w + size_t(x)] +=
                        c.w * ((1.0f - f) * src[3 * i0 + int(ch)] + f * src[3 * i1 + int(ch)]);
            }
        }
    }
}

} // namespace

PrefilterSource prefilterSource(const EnvironmentImage& env,
                                const std::vector<EnvironmentImage>& mips) {
    // The levels are prefiltered from the sky with its bright texels capped (kBrightCap), and
    // the capped rest added exactly.
    double power = 0.0;
    for (int y = 0; y < env.height; ++y) {
        double row = 0.0;
        for (int x = 0; x < env.width; ++x) {
            const glm::vec3 c = env.texel(x, y);
            row += 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
        }
        power += row * env.texelSolidAngle(y);
    }
    const double cap = kBrightCap * power / (4.0 * kPiD);
    PrefilterSource source;
    source.sky = &env;
    EnvironmentImage capped;
    for (int y = 0; y < env.height && cap > 0.0; ++y)
        for (int x = 0; x < env.width; ++x) {
            const glm::vec3 c = env.texel(x, y);
            const double lum = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
            if (!(lum > cap)) continue;
            if (capped.rgb.empty()) capped = env;
            const float keep = float(cap / lum);
            float* q = &capped.rgb[3 * (size_t(y) * size_t(env.width) + size_t(x))];
            for (int ch = 0; ch < 3; ++ch)
                q[ch] = c[ch] * keep;
            source.bright.push_back({x, y, c - c * keep});
        }
    // The mips the prefilter reads: the environment's own, or those of its capped or
    // power-of-two copy.
    const bool evenMips = (env.width & (env.width - 1)) == 0 && 2 * env.height == env.width;
    source.mips = &mips;
    if (!source.bright.empty() || !evenMips) {
        source.ownMips.push_back(powerOfTwo(source.bright.empty() ? env : std::move(capped)));
        while (source.ownMips.back().height > 16)
            source.ownMips.push_back(source.ownMips.back().downsampled());
        source.mips = &source.ownMips;
    }
    return source;
}

// Prefilters one level: for each texel direction R (with N = V = R, the split sum's
// assumption), the environment through the GGX lobe about R, Σ L(l) D(h) n·l / Σ D(h) n·l,
// by a deterministic quadrature over the source mips (filtered importance sampling, Křivánek &
// Colbert 2008, done as a sum over cells whose size follows the lobe instead of over random
// samples; quadratureCells), found once a row and turned for each of its texels
// (accumulateRow). The sky's bright rest (kBrightCap) is added exactly, as points in cells at
// most 2α / 3 wide. Every row is summed in a fixed order: the result does not depend on the
// thread count.
EnvironmentImage prefilter(const PrefilterSource& source, int width, float roughness, double cell,
                           int nthreads, const std::atomic<bool>* cancel) {
    const std::vector<EnvironmentImage>& mips = *source.mips;
    EnvironmentImage out;
    out.width = width;
    out.height = width / 2;
    out.rgb.assign(size_t(out.width) * size_t(out.height) * 3, 0.0f);
    const int W = out.width, H = out.height;
    const float alpha = std::max(roughness * roughness, kMinAlpha);

    BrightPoints points;
    float pointScale = 0.0f;
    if (!source.bright.empty()) {
        const EnvironmentImage& sky = *source.sky;
        int shift = 0;
        while ((sky.height >> (shift + 1)) >= 4 &&
               2.0 * kPiD / sky.width * double(2 << shift) <= 2.0 * alpha / 3.0)
            ++shift;
        points = brightPoints(source.bright, sky, shift);
        pointScale = float(1.0 / ggxMeanCosine(alpha));
    }

    const std::vector<std::vector<Cell>> cells =
        quadratureCells(mips, W, alpha, cell, nthreads, cancel);
    if (cancel && cancel->load(std::memory_order_relaxed)) return out;
    const std::vector<Plane> planes = mipPlanes(mips, cells, W, nthreads);
    OIIO::parallel_for(
        0, H,
        [&](int64_t y) {
            if (cancel && cancel->load(std::memory_order_relaxed)) return;
            std::vector<float> acc(size_t(W) * 3, 0.0f); // planar
            accumulateRow(cells[size_t(y)], planes, mips, W, acc.data());
            const double theta = kPiD * (double(y) + 0.5) / H;
            for (int x = 0; x < W; ++x) {
                glm::vec3 v(acc[size_t(x)], acc[size_t(W + x)], acc[size_t(2 * W + x)]);
                if (points.size()) {
                    const double phi = 2.0 * kPiD * ((x + 0.5) / W - 0.5);
                    const glm::vec3 R(glm::dvec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                                 std::sin(theta) * std::sin(phi)));
                    v += pointScale * brightLobe(points, R, alpha);
                }
                float* p = &out.rgb[3 * (size_t(y) * size_t(W) + size_t(x))];
                p[0] = v.r;
                p[1] = v.g;
                p[2] = v.b;
            }
        },
        perItem(nthreads));
    return out;
}

} // namespace dhdr
