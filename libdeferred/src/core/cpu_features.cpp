#include <cstdlib>
#include <dhdr/deferred/core/cpu_features.h>

namespace dhdr {

bool embreeIsaSupported(const std::string& isa) {
    __builtin_cpu_init();
    if (isa == "sse2") return __builtin_cpu_supports("sse2");
    if (isa == "sse4.2") return __builtin_cpu_supports("sse4.2");
    if (isa == "avx") return __builtin_cpu_supports("avx");
    if (isa == "avx2") return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    // Embree's AVX-512 kernels are its SKX target.
    if (isa == "avx512")
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
               __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512bw") &&
               __builtin_cpu_supports("avx512vl");
    return false;
}

std::string embreeIsaRequested() {
    const char* isa = std::getenv("DHDR_EMBREE_ISA");
    return isa ? std::string(isa) : std::string();
}

} // namespace dhdr
