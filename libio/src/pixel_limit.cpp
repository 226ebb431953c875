#include <algorithm>
#include <atomic>
#include <cmath>
#include <dhdr/io/pixel_limit.h>

namespace dhdr {

namespace {
// Set once by a tool's --max-pixels, read by readers on any thread.
std::atomic<long long> g_maxPixels{kDefaultMaxPixels};
constexpr const char* kPixelLimitText = " pixels is more than --max-pixels ";
} // namespace

long long maxPixels() {
    return g_maxPixels;
}
void setMaxPixels(long long pixels) {
    g_maxPixels = pixels;
}

std::string pixelLimitError(long long width, long long height, long long depth) {
    const long long limit = g_maxPixels;
    if (limit <= 0) return {};
    // In long double: a header's sizes can multiply past 2^63.
    const long double pixels =
        (long double)width * (long double)height * (long double)std::max(depth, 1LL);
    if (pixels <= (long double)limit) return {};
    std::string text = std::to_string(width) + "x" + std::to_string(height) +
                       (depth > 1 ? "x" + std::to_string(depth) : std::string()) + kPixelLimitText +
                       std::to_string(limit);
    const long long side = std::llround(std::sqrt(double(limit)));
    if (side * side == limit)
        text += " (" + std::to_string(side) + "x" + std::to_string(side) + ")";
    return text + "; give --max-pixels to raise it";
}

bool isPixelLimitError(const std::string& error) {
    return error.find(kPixelLimitText) != std::string::npos &&
           error.find("; give --max-pixels to raise it") != std::string::npos;
}

} // namespace dhdr
