// How far the prefiltered IBL levels are from the integral they stand for. For each HDRI, with
// and without the sun split off (sun thresholds 10 and 0), bakeIbl with default parameters
// (timed, once as it is and once with a trivial DFG table: the levels' own cost); then each
// level k ≥ 1 read at ~400 directions R, a Hammersley set on the sphere, bilinear between the
// level's texels as shading reads it ("@R"), and at the centre of R's texel, the prefilter's
// own estimate ("@C"), against a brute-force integral of the same GGX lobe (N = V = R, weights
// n·l: the split sum's prefiltered radiance, Σ L(l) n·l / Σ n·l over GGX samples in the limit)
// over the full-resolution sky the levels were baked from (level 0), in double, with point
// (bilinear) lookups. Errors are relative, on luminance: |P − ref| / max(ref, 10⁻³ × the
// sky's mean luminance); mean, 95th percentile and mean signed ("bias").
//
// The reference: the sky with each texel's luminance capped at --cap × its mean (20) by GGX
// importance sampling (--ref-samples half vectors, a Hammersley set rotated per direction),
// the bright rest (the sun, lamps: a few texels that would need millions of samples) by
// quadrature (SplitSky). At every eighth direction a second reference, another rotation and a
// quadrature twice as fine, estimates the reference's own error ("noise", |a − b| / √2).
//
// Usage: dhdr-bench-prefilter [--directions N] [--ref-samples N] [--samples N] [--cap C]
//        [--sun-thresholds T,T] [--threads N] [--bake-threads N] [HDRI.exr ...]
// --samples sets IblBakeParams::samples; bakes run on --bake-threads (1), the reference on
// --threads (all). Default HDRIs: Blender's eight studio-light worlds (Poly Haven, CC0).
#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dhdr/common/parallel.h>
#include <dhdr/deferred/core/sampling.h>
#include <dhdr/deferred/environment/ibl.h>
#include <map>
#include <string>
#include <thread>
#include <vector>

using namespace dhdr;

namespace {

const char* const kDefaultHdris[] = {"city",  "courtyard", "forest",  "interior",
                                     "night", "studio",    "sunrise", "sunset"};
const char* const kDefaultFolder = "/usr/share/blender/datafiles/studiolights/world/";

double luminance(const glm::dvec3& c) {
    return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

// Direction i of n, uniform on the sphere (Y up): a Hammersley set in (cos θ, φ).
glm::vec3 sphereDirection(int i, int n) {
    const double y = 1.0 - 2.0 * (double(i) + 0.5) / double(n);
    const double phi = 2.0 * 3.14159265358979323846 * double(radicalInverse2(std::uint32_t(i)));
    const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
    return glm::vec3(glm::dvec3(r * std::cos(phi), y, r * std::sin(phi)));
}

// The centre of the texel of `level` that d lies in.
glm::vec3 texelCentre(const EnvironmentImage& level, const glm::vec3& d) {
    const glm::vec2 uv = equirectUV(d);
    const int x = std::clamp(int(uv.x * float(level.width)), 0, level.width - 1);
    const int y = std::clamp(int(uv.y * float(level.height)), 0, level.height - 1);
    return equirectDirection(
        {(float(x) + 0.5f) / float(level.width), (float(y) + 0.5f) / float(level.height)});
}

constexpr double kPiD = 3.14159265358979323846;

// The sky split for the reference: `smooth`, each texel's luminance capped at `cap` (its
// chroma kept), integrated by Monte Carlo; and the rest (the sun and other few bright texels,
// where importance sampling the lobe alone would need millions of samples), integrated by
// quadrature: the bilinear reconstruction is linear, so bilinear(sky) = bilinear(smooth) +
// bilinear(rest) exactly, and bilinear(rest) is zero outside the bright texels' cells and
// their 8 neighbours, which are cut into m × m cells read at their centres.
struct SplitSky {
    EnvironmentImage smooth;
    struct Point {
        glm::dvec3 d; // unit direction
        double y;     // luminance of bilinear(rest) there times the cell's solid angle
    };
    std::vector<Point> coarse, fine; // m and 2m cells a texel
    long long brightTexels = 0;
    double brightShare = 0.0; // of the sky's ∫ Y dω
};

std::vector<SplitSky::Point> quadrature(const EnvironmentImage& rest,
                                        const std::vector<char>& support, int m) {
    std::vector<SplitSky::Point> points;
    const int w = rest.width, h = rest.height;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (!support[size_t(y) * size_t(w) + size_t(x)]) continue;
            for (int b = 0; b < m; ++b) {
                const double t0 = (double(y) + double(b) / m) / h;
                const double t1 = (double(y) + double(b + 1) / m) / h;
                const double omega =
                    2.0 * kPiD / (double(w) * m) * (std::cos(kPiD * t0) - std::cos(kPiD * t1));
                for (int a = 0; a < m; ++a) {
                    const double u = (double(x) + (double(a) + 0.5) / m) / w;
                    const double t = 0.5 * (t0 + t1);
                    const double yv =
                        luminance(glm::dvec3(rest.bilinear(glm::vec2(float(u), float(t)))));
                    if (yv == 0.0) continue;
                    const double phi = (u - 0.5) * 2.0 * kPiD, theta = t * kPiD;
                    const glm::dvec3 d(std::sin(theta) * std::cos(phi), std::cos(theta),
                                       std::sin(theta) * std::sin(phi));
                    points.push_back({d, yv * omega});
                }
            }
        }
    return points;
}

SplitSky splitSky(const EnvironmentImage& sky, double cap) {
    SplitSky s;
    s.smooth = sky;
    EnvironmentImage rest = sky;
    const int w = sky.width, h = sky.height;
    std::vector<char> support(size_t(w) * size_t(h), 0);
    double total = 0.0, bright = 0.0;
    for (int y = 0; y < h; ++y) {
        const double omega = sky.texelSolidAngle(y);
        for (int x = 0; x < w; ++x) {
            const size_t i = size_t(y) * size_t(w) + size_t(x);
            const glm::vec3 c = sky.texel(x, y);
            const double yv = luminance(glm::dvec3(c));
            total += yv * omega;
            const float keep = yv > cap ? float(cap / yv) : 1.0f;
            for (int ch = 0; ch < 3; ++ch) {
                s.smooth.rgb[3 * i + size_t(ch)] = c[ch] * keep;
                rest.rgb[3 * i + size_t(ch)] = c[ch] - c[ch] * keep;
            }
            if (yv > cap) {
                ++s.brightTexels;
                bright += (yv - cap) * omega;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int yy = std::clamp(y + dy, 0, h - 1);
                        const int xx = ((x + dx) % w + w) % w;
                        support[size_t(yy) * size_t(w) + size_t(xx)] = 1;
                    }
            }
        }
    }
    s.brightShare = total > 0.0 ? bright / total : 0.0;
    s.coarse = quadrature(rest, support, 4);
    s.fine = quadrature(rest, support, 8);
    return s;
}

// E[max(0, n·l)] over GGX half vectors (N = V): the normalization of Σ L(l) n·l / Σ n·l, by
// the midpoint rule in the one variable n·l depends on.
double meanCosine(double alpha) {
    const int n = 1 << 20;
    const double a2 = alpha * alpha;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double u = (double(i) + 0.5) / n;
        const double c2 = (1.0 - u) / (1.0 + (a2 - 1.0) * u);
        sum += std::max(0.0, 2.0 * c2 - 1.0);
    }
    return sum / n;
}

// The luminance of the split sum's prefiltered radiance along R by brute force, Σ L(l) n·l /
// Σ n·l over GGX-importance-sampled l (Walter et al. 2007) in the limit: the smooth sky by
// `samples` half vectors from a Hammersley set rotated by `seed`, each a bilinear lookup of
// the full-resolution image; the bright rest by its quadrature points, each weighted by the
// samples' density D(h) / 4 and n·l.
double reference(const SplitSky& sky, const std::vector<SplitSky::Point>& points,
                 const glm::vec3& R, float roughness, double cosineMean, int samples,
                 std::uint64_t seed) {
    const double alpha = std::max(double(roughness) * double(roughness), double(kMinAlpha));
    const double a2 = alpha * alpha;
    glm::vec3 tf, bf;
    orthonormalBasis(R, tf, bf);
    const glm::dvec3 t(tf), b(bf), n(R);
    const RotatedHammersley set(seed);
    double sum = 0.0, weight = 0.0;
    for (int i = 0; i < samples; ++i) {
        const glm::vec2 u = set(std::uint32_t(i), std::uint32_t(samples));
        const double cosTheta = std::sqrt((1.0 - u.x) / (1.0 + (a2 - 1.0) * u.x));
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
        const double phi = 2.0 * kPiD * u.y;
        const glm::dvec3 h(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
        const glm::dvec3 l = 2.0 * h.z * h - glm::dvec3(0, 0, 1);
        if (l.z <= 0.0) continue;
        const glm::dvec3 d = glm::normalize(t * l.x + b * l.y + n * l.z);
        sum += luminance(glm::dvec3(sky.smooth.radiance(glm::vec3(d)))) * l.z;
        weight += l.z;
    }
    double bright = 0.0;
    for (const SplitSky::Point& p : points) {
        const double nl = glm::dot(n, p.d);
        if (nl <= 0.0) continue;
        // n·h for h = normalize(n + l): √((1 + n·l) / 2).
        const double nh2 = 0.5 * (1.0 + nl);
        const double den = nh2 * (a2 - 1.0) + 1.0;
        bright += p.y * nl * a2 / (kPiD * den * den) / 4.0;
    }
    return sum / std::max(weight, 1e-300) + bright / cosineMean;
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t i = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
    return v[i];
}

double mean(const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v)
        s += x;
    return v.empty() ? 0.0 : s / double(v.size());
}

struct LevelStats {
    double meanR = 0, p95R = 0, meanC = 0, p95C = 0, biasR = 0, noiseMean = 0, noiseP95 = 0;
};

struct Options {
    int directions = 400;
    int refSamples = 16384;
    int samples = 128;
    int threads = 0;
    int bakeThreads = 1;
    double cap = 20.0;
    std::vector<float> sunThresholds = {10.0f, 0.0f};
    std::vector<std::string> hdris;
};

bool parse(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&](int lo, int hi, int& out) {
            if (i + 1 >= argc) return false;
            out = std::atoi(argv[++i]);
            return out >= lo && out <= hi;
        };
        if (a == "--directions") {
            if (!value(8, 1 << 20, o.directions)) return false;
        } else if (a == "--ref-samples") {
            if (!value(16, 1 << 24, o.refSamples)) return false;
        } else if (a == "--samples") {
            if (!value(1, 65536, o.samples)) return false;
        } else if (a == "--threads") {
            if (!value(0, 1024, o.threads)) return false;
        } else if (a == "--bake-threads") {
            if (!value(0, 1024, o.bakeThreads)) return false;
        } else if (a == "--cap") {
            if (i + 1 >= argc) return false;
            o.cap = std::atof(argv[++i]);
            if (!(o.cap > 0.0)) return false;
        } else if (a == "--sun-thresholds") {
            if (i + 1 >= argc) return false;
            o.sunThresholds.clear();
            for (const char* p = argv[++i]; *p;) {
                char* end = nullptr;
                const float t = std::strtof(p, &end);
                if (end == p || !(t >= 0.0f)) return false;
                o.sunThresholds.push_back(t);
                p = *end == ',' ? end + 1 : end;
                if (*end && *end != ',') return false;
            }
        } else if (a.size() > 1 && a[0] == '-') {
            return false;
        } else {
            o.hdris.push_back(a);
        }
    }
    if (o.hdris.empty())
        for (const char* name : kDefaultHdris)
            o.hdris.push_back(std::string(kDefaultFolder) + name + ".exr");
    return !o.sunThresholds.empty();
}

std::string stem(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    std::string s = slash == std::string::npos ? path : path.substr(slash + 1);
    const size_t dot = s.find_last_of('.');
    return dot == std::string::npos ? s : s.substr(0, dot);
}

} // namespace

int main(int argc, char** argv) {
    Options o;
    if (!parse(argc, argv, o)) {
        std::fprintf(stderr, "usage: dhdr-bench-prefilter [--directions N] [--ref-samples N] "
                             "[--samples N] [--cap C]\n       [--sun-thresholds T,T] [--threads N] "
                             "[--bake-threads N] [HDRI.exr ...]\n");
        return 2;
    }
    const int threads = o.threads > 0 ? o.threads : int(std::thread::hardware_concurrency());
    std::printf("prefiltered levels against brute-force GGX: %d directions, %d reference "
                "samples each, bake: %d samples per texel, %d thread(s); reference: %d thread(s)\n",
                o.directions, o.refSamples, o.samples, o.bakeThreads, threads);
    std::printf(
        "rel. error of luminance: at R = bilinear read of the level at the direction, "
        "at C = at its texel's centre;\nnoise = the reference's own (another rotation and a "
        "finer quadrature at every 8th direction, |a − b| / √2)\n\n");
    std::printf("%-10s %5s %6s %8s %8s  %2s %5s %5s  %8s %8s %8s  %8s %8s  %8s %8s\n", "hdri",
                "sun", "share", "bake s", "noDFG s", "k", "rough", "width", "mean@R", "p95@R",
                "bias@R", "mean@C", "p95@C", "noise", "noiseP95");
    // Per (sun threshold, level): the per-HDRI statistics, for the summary.
    std::map<std::pair<float, int>, std::vector<LevelStats>> all;
    std::map<float, std::vector<double>> bakeTimes, levelTimes;
    const auto start = std::chrono::steady_clock::now();
    for (const std::string& path : o.hdris) {
        EnvironmentImage env;
        std::string error;
        if (!readEnvironmentImage(path, env, error)) {
            std::fprintf(stderr, "%s: %s\n", path.c_str(), error.c_str());
            return 1;
        }
        for (const float threshold : o.sunThresholds) {
            IblBakeParams params;
            params.sunThreshold = threshold;
            params.samples = o.samples;
            Ibl ibl;
            auto t0 = std::chrono::steady_clock::now();
            if (!bakeIbl(env, params, ibl, error, o.bakeThreads)) {
                std::fprintf(stderr, "%s: %s\n", path.c_str(), error.c_str());
                return 1;
            }
            auto t1 = std::chrono::steady_clock::now();
            // The same bake with a trivial DFG table: its levels are the same, its time is
            // the sun, SH, sampler and levels alone (what a prefilter change moves).
            IblBakeParams noDfg = params;
            noDfg.dfgSize = 2;
            noDfg.dfgSamples = 1;
            Ibl levelsOnly;
            bakeIbl(env, noDfg, levelsOnly, error, o.bakeThreads);
            auto t2 = std::chrono::steady_clock::now();
            const double bakeSeconds = std::chrono::duration<double>(t1 - t0).count();
            const double levelSeconds = std::chrono::duration<double>(t2 - t1).count();
            bakeTimes[threshold].push_back(bakeSeconds);
            levelTimes[threshold].push_back(levelSeconds);

            // Level 0 is the sky the levels were baked from (the sun taken out, if any).
            const EnvironmentImage& sky = ibl.levels[0];
            double power = 0.0;
            for (int y = 0; y < sky.height; ++y) {
                double row = 0.0;
                for (int x = 0; x < sky.width; ++x)
                    row += luminance(glm::dvec3(sky.texel(x, y)));
                power += row * sky.texelSolidAngle(y);
            }
            const double meanY = power / (4.0 * kPiD);
            const double floorY = 1e-3 * meanY;
            const SplitSky split = splitSky(sky, o.cap * meanY);
            std::printf("# %s, sun threshold %g: reference over %d x %d, %lld texels above "
                        "%g x the mean (%.1f %% of the light) by quadrature, %zu points\n",
                        stem(path).c_str(), double(threshold), sky.width, sky.height,
                        split.brightTexels, o.cap, 100.0 * split.brightShare, split.coarse.size());

            for (int k = 1; k < int(ibl.levels.size()); ++k) {
                const EnvironmentImage& level = ibl.levels[size_t(k)];
                const float roughness = iblLevelRoughness(k, params.levels);
                const double cosineMean =
                    meanCosine(std::max(double(roughness) * roughness, double(kMinAlpha)));
                const int n = o.directions;
                const size_t count = static_cast<size_t>(n);
                std::vector<double> errR(count), errC(count), signedR(count);
                std::vector<double> noise(count, -1.0);
                OIIO::parallel_for(
                    0, n,
                    [&](int64_t i) {
                        auto ref = [&](const glm::vec3& d, int set, bool fine) {
                            return reference(split, fine ? split.fine : split.coarse, d, roughness,
                                             cosineMean, o.refSamples,
                                             sampleSeed(i, k, set, 0x70726566));
                        };
                        const glm::vec3 R = sphereDirection(int(i), n);
                        const glm::vec3 C = texelCentre(level, R);
                        const double refR = ref(R, 1, false), refC = ref(C, 2, false);
                        const double atR = luminance(glm::dvec3(level.radiance(R)));
                        const double atC = luminance(glm::dvec3(level.radiance(C)));
                        errR[size_t(i)] = std::abs(atR - refR) / std::max(refR, floorY);
                        signedR[size_t(i)] = (atR - refR) / std::max(refR, floorY);
                        errC[size_t(i)] = std::abs(atC - refC) / std::max(refC, floorY);
                        // Another Hammersley rotation and a finer quadrature of the rest.
                        if (i % 8 == 0)
                            noise[size_t(i)] = std::abs(ref(R, 3, true) - refR) /
                                               std::max(refR, floorY) / std::sqrt(2.0);
                    },
                    perItem(threads));
                noise.erase(std::remove(noise.begin(), noise.end(), -1.0), noise.end());
                LevelStats s;
                s.meanR = mean(errR);
                s.p95R = percentile(errR, 0.95);
                s.biasR = mean(signedR);
                s.meanC = mean(errC);
                s.p95C = percentile(errC, 0.95);
                s.noiseMean = mean(noise);
                s.noiseP95 = percentile(noise, 0.95);
                all[{threshold, k}].push_back(s);
                std::printf("%-10s %5g %5.1f%% %8.3f %8.3f  %2d %5.2f %5d  %7.2f%% %7.2f%% "
                            "%+7.2f%%  %7.2f%% %7.2f%%  %7.3f%% %7.3f%%\n",
                            stem(path).c_str(), double(threshold), 100.0 * ibl.sun.share,
                            bakeSeconds, levelSeconds, k, double(roughness), level.width,
                            100.0 * s.meanR, 100.0 * s.p95R, 100.0 * s.biasR, 100.0 * s.meanC,
                            100.0 * s.p95C, 100.0 * s.noiseMean, 100.0 * s.noiseP95);
                std::fflush(stdout);
            }
        }
    }
    std::printf("\nsummary over %zu HDRIs (the mean of each HDRI's statistic)\n", o.hdris.size());
    std::printf("%5s %8s %8s  %2s  %8s %8s %8s  %8s %8s  %8s\n", "sun", "bake s", "noDFG s", "k",
                "mean@R", "p95@R", "bias@R", "mean@C", "p95@C", "noise");
    for (const float threshold : o.sunThresholds)
        for (int k = 1;; ++k) {
            const auto it = all.find({threshold, k});
            if (it == all.end()) break;
            LevelStats m;
            for (const LevelStats& s : it->second) {
                m.meanR += s.meanR;
                m.p95R += s.p95R;
                m.biasR += s.biasR;
                m.meanC += s.meanC;
                m.p95C += s.p95C;
                m.noiseMean += s.noiseMean;
            }
            const double c = 100.0 / double(it->second.size());
            std::printf("%5g %8.3f %8.3f  %2d  %7.2f%% %7.2f%% %+7.2f%%  %7.2f%% %7.2f%%  "
                        "%7.3f%%\n",
                        double(threshold), mean(bakeTimes[threshold]), mean(levelTimes[threshold]),
                        k, c * m.meanR, c * m.p95R, c * m.biasR, c * m.meanC, c * m.p95C,
                        c * m.noiseMean);
        }
    std::printf("total %.1f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return 0;
}
