#include <algorithm>
#include <cmath>
#include <dhdr/deferred/environment/sun.h>
#include <vector>

namespace dhdr {

namespace {

double luminance(const glm::dvec3& c) {
    return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

} // namespace

EnvironmentSun extractSun(EnvironmentImage& env, float threshold) {
    EnvironmentSun sun;
    sun.threshold = threshold;
    if (!(threshold > 0.0f) || env.width <= 0 || env.height <= 0) return sun;
    const int w = env.width, h = env.height;
    auto lum = [&](int x, int y) { return luminance(glm::dvec3(env.texel(x, y))); };
    // The brightest texel, and the environment's luminance power, in a fixed order.
    int bx = 0, by = 0;
    double brightest = -1.0, power = 0.0;
    for (int y = 0; y < h; ++y) {
        const double omega = env.texelSolidAngle(y);
        for (int x = 0; x < w; ++x) {
            const double l = lum(x, y);
            power += std::max(l, 0.0) * omega;
            if (l > brightest) brightest = l, bx = x, by = y;
        }
    }
    if (!(brightest > double(threshold))) return sun;
    // The connected region above the threshold, breadth first from the brightest texel.
    std::vector<unsigned char> in(size_t(w) * size_t(h), 0);
    std::vector<int> region = {by * w + bx};
    in[size_t(by * w + bx)] = 1;
    for (size_t k = 0; k < region.size(); ++k) {
        const int x0 = region[k] % w, y0 = region[k] / w;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int y = y0 + dy, x = (x0 + dx + w) % w;
                if (y < 0 || y >= h) continue;
                const size_t i = size_t(y) * size_t(w) + size_t(x);
                if (in[i] || !(lum(x, y) > double(threshold))) continue;
                in[i] = 1;
                region.push_back(int(i));
            }
    }
    std::sort(region.begin(), region.end()); // a fixed order for the sums
    // What each texel gives, and the weighted mean direction.
    glm::dvec3 E(0.0), axis(0.0);
    double given = 0.0;
    for (int i : region) {
        const int x = i % w, y = i / w;
        const glm::dvec3 L(env.texel(x, y));
        const double omega = env.texelSolidAngle(y);
        const glm::dvec3 excess = L * (1.0 - double(threshold) / luminance(L));
        const glm::dvec3 d(
            equirectDirection({(float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h)}));
        E += excess * omega;
        axis += luminance(excess) * omega * d;
        given += luminance(excess) * omega;
    }
    if (!(given > 0.0) || glm::length(axis) == 0.0) return sun;
    axis = glm::normalize(axis);
    // The spread about the axis, as a uniform disk's: E[θ²] = r² / 2.
    double spread = 0.0;
    for (int i : region) {
        const int x = i % w, y = i / w;
        const glm::dvec3 L(env.texel(x, y));
        const double omega = env.texelSolidAngle(y);
        const glm::dvec3 d(
            equirectDirection({(float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h)}));
        const double theta = std::acos(std::clamp(glm::dot(d, axis), -1.0, 1.0));
        spread += luminance(L * (1.0 - double(threshold) / luminance(L))) * omega * theta * theta;
    }
    const double texel = 3.14159265358979323846 / double(h);
    const double diameter = std::max(2.0 * std::sqrt(2.0 * spread / given), texel);
    if (diameter > double(kMaxSunAngle)) return sun;
    for (int i : region) {
        float* p = &env.rgb[3 * size_t(i)];
        const double keep = double(threshold) / luminance(glm::dvec3(p[0], p[1], p[2]));
        for (int c = 0; c < 3; ++c)
            p[c] = float(double(p[c]) * keep);
    }
    sun.direction = glm::vec3(axis);
    sun.angle = float(diameter);
    sun.illuminance = glm::vec3(E);
    sun.share = power > 0.0 ? given / power : 0.0;
    return sun;
}

} // namespace dhdr
