// One libFuzzer target of fuzz/targets.h, chosen at compile time by DHDR_FUZZ_TARGET
// (fuzz/CMakeLists.txt builds this file once a target). Never prints; the input goes to a
// per-process temporary file where the API reads a path.
#include "targets.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    dhdr::fuzz::initImageLibraries();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    dhdr::fuzz::DHDR_FUZZ_TARGET(data, size);
    return 0;
}
