// Keyframe interpolation of glTF 2.0's Appendix C.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <dhdr/deferred/scene/animation.h>

namespace dhdr {

namespace {

// A key's value (its middle third for CUBICSPLINE), `n` components.
const float* keyValue(const AnimationSampler& s, size_t key) {
    const size_t n = size_t(s.components);
    return s.interpolation == Interpolation::CubicSpline ? &s.values[(3 * key + 1) * n]
                                                         : &s.values[key * n];
}

void normalise(double* q) {
    const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (len > 0.0 && std::isfinite(len))
        for (int c = 0; c < 4; ++c)
            q[c] /= len;
    else
        q[0] = q[1] = q[2] = 0.0, q[3] = 1.0; // a zero quaternion: no rotation
}

void copyKey(const AnimationSampler& s, size_t key, double* out) {
    const float* v = keyValue(s, key);
    for (int c = 0; c < s.components; ++c)
        out[c] = double(v[c]);
    if (s.rotation) normalise(out);
}

// Appendix C's slerp between unit quaternions a and b, along the shorter arc.
void slerp(const double* a, const double* bIn, double u, double* out) {
    double b[4] = {bIn[0], bIn[1], bIn[2], bIn[3]};
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    if (d < 0.0) {
        for (double& c : b)
            c = -c;
        d = -d;
    }
    if (d > 0.9995) { // nearly parallel: a normalised lerp, which slerp approaches
        for (int c = 0; c < 4; ++c)
            out[c] = (1.0 - u) * a[c] + u * b[c];
        normalise(out);
        return;
    }
    const double theta0 = std::acos(d), theta = u * theta0;
    const double sa = std::cos(theta) - d * std::sin(theta) / std::sin(theta0);
    const double sb = std::sin(theta) / std::sin(theta0);
    for (int c = 0; c < 4; ++c)
        out[c] = sa * a[c] + sb * b[c];
    normalise(out);
}

} // namespace

void AnimationSampler::evaluate(double t, double* out) const {
    const size_t keys = times.size();
    if (keys == 0 || components <= 0) return;
    // Key times are floats: float(N / 24) often exceeds the double N / 24, and a frame's time
    // that rounds to a key is that key's, so that a STEP jumps on the frame its key names.
    if (const float tf = float(t); std::isfinite(tf)) {
        const auto key = std::lower_bound(times.begin(), times.end(), tf);
        if (key != times.end() && *key == tf) t = double(tf);
    }
    // Holds outside the keys; NaN holds the first.
    if (!(t > double(times.front())) || keys == 1) return copyKey(*this, 0, out);
    if (t >= double(times.back())) return copyKey(*this, keys - 1, out);
    // The key interval [k, k + 1] holding t: times[k] <= t < times[k + 1].
    const size_t k = size_t(std::upper_bound(times.begin(), times.end(), t,
                                             [](double v, float key) { return v < double(key); }) -
                            times.begin()) -
                     1;
    const double t0 = double(times[k]), t1 = double(times[k + 1]), td = t1 - t0;
    const double u = (t - t0) / td;
    const size_t n = size_t(components);
    switch (interpolation) {
    case Interpolation::Step:
        return copyKey(*this, k, out);
    case Interpolation::Linear:
        if (rotation) {
            double a[4], b[4];
            copyKey(*this, k, a);
            copyKey(*this, k + 1, b);
            return slerp(a, b, u, out);
        }
        for (size_t c = 0; c < n; ++c)
            out[c] = (1.0 - u) * double(values[k * n + c]) + u * double(values[(k + 1) * n + c]);
        return;
    case Interpolation::CubicSpline: {
        // Hermite with the out-tangent b_k of key k and the in-tangent a_k+1 of key k + 1,
        // both scaled by the interval's length; quaternions normalised after.
        const double u2 = u * u, u3 = u2 * u;
        const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2,
                     h11 = u3 - u2;
        const float* vk = &values[(3 * k + 1) * n];
        const float* bk = &values[(3 * k + 2) * n];
        const float* ak1 = &values[(3 * (k + 1)) * n];
        const float* vk1 = &values[(3 * (k + 1) + 1) * n];
        for (size_t c = 0; c < n; ++c)
            out[c] = h00 * double(vk[c]) + h10 * td * double(bk[c]) + h01 * double(vk1[c]) +
                     h11 * td * double(ak1[c]);
        if (rotation) normalise(out);
        return;
    }
    }
}

bool selectAnimations(const std::vector<Animation>& animations, const std::string& selection,
                      std::vector<int>& chosen, std::string& error) {
    chosen.clear();
    if (animations.empty()) {
        if (selection.empty()) return true;
        error = "--animation " + selection + ": the file has no animations";
        return false;
    }
    if (selection.empty()) {
        chosen = {0};
    } else if (selection == "all") {
        for (size_t i = 0; i < animations.size(); ++i)
            chosen.push_back(int(i));
    } else {
        // A whole number is an index, as the option's INDEX promises, even where another
        // animation is named "0"; a name is matched when no animation has that index.
        const bool digits =
            selection.size() < 10 && selection.find_first_not_of("0123456789") == std::string::npos;
        if (digits && std::stoul(selection) < animations.size())
            chosen = {int(std::stoul(selection))};
        for (size_t i = 0; i < animations.size() && chosen.empty(); ++i)
            if (animations[i].name == selection) chosen = {int(i)};
        if (chosen.empty()) {
            std::string names;
            for (size_t i = 0; i < animations.size(); ++i)
                names += (i ? ", " : "") + std::to_string(i) + " '" + animations[i].name + "'";
            error = "no animation '" + selection + "' (the file has: " + names + ")";
            return false;
        }
    }
    for (const int i : chosen)
        if (!animations[size_t(i)].problem.empty()) {
            error = "animation '" + animations[size_t(i)].name +
                    "' cannot be played: " + animations[size_t(i)].problem;
            return false;
        }
    return true;
}

} // namespace dhdr
