#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <cmath>
#include <dhdr/deferred/core/brdf.h>
#include <dhdr/deferred/core/table_lookup.h>
#include <dhdr/deferred/environment/environment.h>
#include <dhdr/io/exr_header.h>

namespace dhdr {

glm::vec2 equirectUV(const glm::vec3& d) {
    const float u = 0.5f + std::atan2(d.z, d.x) / (2.0f * kPi);
    const float t = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi;
    return {u, t};
}

glm::vec3 equirectDirection(glm::vec2 uv) {
    const float phi = (uv.x - 0.5f) * 2.0f * kPi, theta = uv.y * kPi;
    const float s = std::sin(theta);
    return {s * std::cos(phi), std::cos(theta), s * std::sin(phi)};
}

glm::vec3 EnvironmentImage::bilinear(glm::vec2 uv) const {
    // u wraps and v clamps below; only NaN and ±Inf (a direction that is not one) are clamped
    // here, to the texels either side of the image.
    const float fx = clampForTable(uv.x * float(width) - 0.5f, -1.0f, float(width)),
                fy = clampForTable(uv.y * float(height) - 0.5f, -1.0f, float(height));
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    const float ax = fx - x0f, ay = fy - y0f;
    auto wrapX = [&](int x) { return ((x % width) + width) % width; };
    auto clampY = [&](int y) { return std::clamp(y, 0, height - 1); };
    const int x0 = wrapX(int(x0f)), x1 = wrapX(int(x0f) + 1);
    const int y0 = clampY(int(y0f)), y1 = clampY(int(y0f) + 1);
    return glm::mix(glm::mix(texel(x0, y0), texel(x1, y0), ax),
                    glm::mix(texel(x0, y1), texel(x1, y1), ax), ay);
}

double EnvironmentImage::texelSolidAngle(int y) const {
    // Δφ (cos θ0 − cos θ1): the rows' solid angles add up to exactly 4π.
    const double pi = 3.14159265358979323846;
    const double t0 = pi * double(y) / double(height), t1 = pi * double(y + 1) / double(height);
    return 2.0 * pi / double(width) * (std::cos(t0) - std::cos(t1));
}

EnvironmentImage EnvironmentImage::downsampled() const {
    EnvironmentImage half;
    half.width = std::max(1, width / 2);
    half.height = std::max(1, height / 2);
    half.rgb.assign(size_t(half.width) * size_t(half.height) * 3, 0.0f);
    for (int y = 0; y < half.height; ++y)
        for (int x = 0; x < half.width; ++x) {
            glm::dvec3 sum(0.0);
            double weight = 0.0;
            for (int dy = 0; dy < 2; ++dy)
                for (int dx = 0; dx < 2; ++dx) {
                    const int sx = std::min(2 * x + dx, width - 1);
                    const int sy = std::min(2 * y + dy, height - 1);
                    const double w = texelSolidAngle(sy);
                    sum += glm::dvec3(texel(sx, sy)) * w;
                    weight += w;
                }
            const glm::vec3 v(sum / std::max(weight, 1e-300));
            float* p = &half.rgb[3 * (size_t(y) * size_t(half.width) + size_t(x))];
            p[0] = v.r;
            p[1] = v.g;
            p[2] = v.b;
        }
    return half;
}

namespace {

// Which channels of `spec` are R, G and B (the same one three times for grey); false when none
// can be.
bool colourChannels(const OIIO::ImageSpec& spec, int rgb[3]) {
    const int r = spec.channelindex("R"), g = spec.channelindex("G"), b = spec.channelindex("B");
    if (r >= 0 && g >= 0 && b >= 0) {
        rgb[0] = r, rgb[1] = g, rgb[2] = b;
        return true;
    }
    int grey = spec.channelindex("Y");
    if (grey < 0 && spec.nchannels <= 2) grey = 0; // Y or Y, A without names
    if (grey < 0 && r >= 0 && spec.nchannels < 3) grey = r;
    if (grey >= 0) {
        rgb[0] = rgb[1] = rgb[2] = grey;
        return true;
    }
    if (spec.nchannels < 3) return false;
    rgb[0] = 0, rgb[1] = 1, rgb[2] = 2;
    return true;
}

// Why an image of `spec`'s size cannot be an environment, or "".
std::string shapeProblem(const OIIO::ImageSpec& spec) {
    const std::string size = std::to_string(spec.width) + "x" + std::to_string(spec.height);
    if (spec.width != 2 * spec.height)
        return "an equirectangular environment is twice as wide as it is high; this one is " + size;
    // 2x1 is 2:1: what refuses it is a minimum size, and the message says so.
    if (spec.height < 2) return "an environment is at least 4x2 texels; this one is " + size;
    if (double(spec.width) * double(spec.height) > double(kMaxEnvironmentTexels))
        return std::to_string(spec.width) + "x" + std::to_string(spec.height) +
               " is larger than an environment may be (16384x8192)";
    return "";
}

} // namespace

bool environmentFromPixels(const OIIO::ImageSpec& spec, const float* pixels, EnvironmentImage& env,
                           std::string& error, long long* replaced) {
    if (error = shapeProblem(spec); !error.empty()) return false;
    int rgb[3];
    if (!colourChannels(spec, rgb)) {
        error = "no colour channels (R, G, B or Y)";
        return false;
    }
    const int nch = spec.nchannels;
    const size_t texels = size_t(spec.width) * size_t(spec.height);
    env.width = spec.width;
    env.height = spec.height;
    env.rgb.assign(texels * 3, 0.0f);
    long long bad = 0;
    for (size_t i = 0; i < texels; ++i)
        for (int c = 0; c < 3; ++c) {
            float v = pixels[i * size_t(nch) + size_t(rgb[c])];
            if (!std::isfinite(v)) {
                v = 0.0f;
                ++bad;
            }
            env.rgb[3 * i + size_t(c)] = v;
        }
    if (replaced) *replaced = bad;
    return true;
}

bool readEnvironmentImage(const std::string& path, EnvironmentImage& env, std::string& error,
                          long long* replaced, int subimage) {
    // The header first: its size and channels decide before any pixel is allocated. The
    // pixels come from the same open file: through an ImageBuf they came from OpenImageIO's
    // shared ImageCache, whose header of a path read before (since rewritten) could be
    // smaller than this one and was overrun (found by fuzz_ibl).
    if (!detail::exrHeadersFit(path, error)) return false;
    auto in = OIIO::ImageInput::open(path);
    if (!in || !in->seek_subimage(subimage, 0)) {
        error = "cannot read: " + (in ? in->geterror() : OIIO::geterror());
        return false;
    }
    const OIIO::ImageSpec spec = in->spec();
    if (spec.deep) {
        error = "a deep image is not an environment";
        return false;
    }
    if (error = shapeProblem(spec); !error.empty()) return false;
    int rgb[3];
    if (!colourChannels(spec, rgb)) {
        error = "no colour channels (R, G, B or Y)";
        return false;
    }
    const int nch = spec.nchannels;
    std::vector<float> src(size_t(spec.width) * size_t(spec.height) * size_t(nch));
    if (!in->read_image(subimage, 0, 0, nch, OIIO::TypeDesc::FLOAT, src.data())) {
        error = "cannot read: " + in->geterror();
        return false;
    }
    return environmentFromPixels(spec, src.data(), env, error, replaced);
}

} // namespace dhdr
