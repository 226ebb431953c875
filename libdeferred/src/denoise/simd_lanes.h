// W floats at once as GCC/Clang vector extensions, for kernels written once and compiled for
// several widths: 4 lanes (SSE2, every x86-64 CPU) and 8 (inside a target("avx2") function,
// which these always-inlined helpers take on). Only exact IEEE operations (no fused
// multiply-adds: "avx2" does not enable FMA), so a lane's result is the same bits at either
// width and on every CPU; min and max are SSE's (the second operand when unordered).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

// 32-byte vectors passed between these helpers never cross a call: they are always inlined.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

namespace dhdr::simd {

#define DHDR_LANES_INLINE [[gnu::always_inline]] inline

template <int W>
struct Lanes {
    typedef float F __attribute__((vector_size(4 * W)));
    typedef std::int32_t I __attribute__((vector_size(4 * W)));
};

template <int W>
DHDR_LANES_INLINE typename Lanes<W>::F load(const float* p) {
    typename Lanes<W>::F v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

template <int W>
DHDR_LANES_INLINE typename Lanes<W>::I load(const std::int32_t* p) {
    typename Lanes<W>::I v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

template <class F>
DHDR_LANES_INLINE void store(const F& v, float* p) {
    std::memcpy(p, &v, sizeof v);
}

// x − (+0) is x for every x, −0 included.
template <class F>
DHDR_LANES_INLINE F splat(float s) {
    return s - F{};
}

template <class F>
using Mask = decltype(F{} < F{});

// n vectors V held as their elements. A container of V itself would not do: outside AVX code a
// 32-byte vector type is aligned to 16 (so std::vector allocates it so), and AVX code moves it
// with instructions that need 32.
template <class V>
class Array {
public:
    using T = std::remove_cv_t<std::remove_reference_t<decltype(V{}[0])>>;
    static constexpr size_t kWidth = sizeof(V) / sizeof(T);
    explicit Array(size_t n) : m_values(n * kWidth, T(0)) {}
    DHDR_LANES_INLINE V operator[](size_t i) const {
        V v;
        std::memcpy(&v, m_values.data() + i * kWidth, sizeof v);
        return v;
    }
    DHDR_LANES_INLINE void set(size_t i, const V& v) {
        std::memcpy(m_values.data() + i * kWidth, &v, sizeof v);
    }

private:
    std::vector<T> m_values;
};

template <class F>
DHDR_LANES_INLINE F select(const Mask<F>& m, const F& a, const F& b) {
    using I = Mask<F>;
    return (F)(((I)a & m) | ((I)b & ~m));
}

template <class F>
DHDR_LANES_INLINE F min(const F& a, const F& b) {
    return select<F>(a < b, a, b);
}
template <class F>
DHDR_LANES_INLINE F max(const F& a, const F& b) {
    return select<F>(a > b, a, b);
}

template <class F>
DHDR_LANES_INLINE F abs(const F& a) {
    using I = Mask<F>;
    return (F)((I)a & 0x7fffffff);
}

template <class I>
DHDR_LANES_INLINE bool any(const I& m) {
    bool a = false;
    for (int l = 0; l < int(sizeof m / sizeof m[0]); ++l)
        a |= m[l] != 0;
    return a;
}

template <class F>
DHDR_LANES_INLINE F sqrt(const F& a) {
    F r = a;
    for (int l = 0; l < int(sizeof a / sizeof a[0]); ++l)
        r[l] = __builtin_sqrtf(a[l]);
    return r;
}

// exp(x) for x ≤ 0 (1 above, 0 below −87), Cephes' expf: x = z ln 2 + r with ln 2 in two parts
// (z ln 2 exact for the reduction), |r| ≤ ½ ln 2, e^r by its polynomial, times 2^z from the
// exponent bits. libm's expf has FMA and non-FMA variants that may differ in the last bit.
template <class F>
DHDR_LANES_INLINE F expNegative(const F& x) {
    using I = Mask<F>;
    const F inRange = min<F>(max<F>(x, splat<F>(-87.0f)), splat<F>(0.0f));
    const F u = inRange * splat<F>(1.44269504088896341f) + splat<F>(0.5f);
    F z = __builtin_convertvector(__builtin_convertvector(u, I), F); // toward 0, then the floor
    z = select<F>(z > u, z - splat<F>(1.0f), z);
    F r = inRange - z * splat<F>(0.693359375f);
    r = r - z * splat<F>(-2.12194440e-4f);
    F p = splat<F>(1.9875691500e-4f);
    p = p * r + splat<F>(1.3981999507e-3f);
    p = p * r + splat<F>(8.3334519073e-3f);
    p = p * r + splat<F>(4.1665795894e-2f);
    p = p * r + splat<F>(1.6666665459e-1f);
    p = p * r + splat<F>(5.0000001201e-1f);
    p = p * (r * r) + r + splat<F>(1.0f);
    const F scale = (F)((__builtin_convertvector(z, I) + 127) << 23);
    return select<F>(x > splat<F>(-87.0f), select<F>(x < splat<F>(0.0f), p * scale, splat<F>(1.0f)),
                     splat<F>(0.0f));
}

} // namespace dhdr::simd

#pragma GCC diagnostic pop
