#include "banded_read.h"

#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace dhdr::app {

namespace {

// Rows per band: a multiple of every OpenEXR compression's lines per chunk, so that no chunk
// is decoded twice (DWAB packs 256 lines, PIZ, B44 and DWAA 32, ZIP 16).
int bandRows(const OIIO::ImageSpec& spec) {
    return spec.get_string_attribute("compression") == "dwab" ? 256 : 64;
}

// How ImageInput::read_native_scanlines packs a pixel of channels [chbegin, chend): each
// channel in its own type, one after the other.
struct NativePixel {
    std::vector<OIIO::TypeDesc> types;
    std::vector<size_t> offsets;
    size_t bytes = 0;
    bool uniform = true;

    NativePixel(const OIIO::ImageSpec& spec, int chbegin, int chend) {
        for (int c = chbegin; c < chend; ++c) {
            types.push_back(spec.channelformat(c));
            offsets.push_back(bytes);
            bytes += types.back().size();
            uniform = uniform && types.back() == types.front();
        }
    }

    // width × height pixels from `native` to float.
    bool toFloat(const std::byte* native, float* pixels, int width, int height) const {
        const int nch = int(types.size());
        if (uniform)
            return OIIO::convert_pixel_values(types[0], native, OIIO::TypeDesc::FLOAT, pixels,
                                              width * height * nch);
        const auto dstPixel = OIIO::stride_t(nch * sizeof(float));
        for (int c = 0; c < nch; ++c)
            if (!OIIO::convert_image(1, width, height, 1, native + offsets[size_t(c)],
                                     types[size_t(c)], OIIO::stride_t(bytes),
                                     OIIO::stride_t(bytes) * width, OIIO::AutoStride, pixels + c,
                                     OIIO::TypeDesc::FLOAT, dstPixel, dstPixel * width,
                                     OIIO::AutoStride))
                return false;
        return true;
    }
};

bool readWhole(const std::string& path, OIIO::ImageBuf& image, int chbegin, int chend,
               std::string& error) {
    image.reset(path);
    if (!image.read(0, 0, chbegin, chend, true, OIIO::TypeDesc::FLOAT)) {
        error = image.geterror();
        return false;
    }
    return true;
}

} // namespace

bool readBanded(const std::string& path, OIIO::ImageBuf& image, int chbegin, int chend,
                int nthreads, std::string& error) {
    std::unique_ptr<OIIO::ImageInput> first = OIIO::ImageInput::open(path);
    if (!first) {
        error = OIIO::geterror();
        return false;
    }
    const OIIO::ImageSpec& fileSpec = first->spec();
    if (std::string(first->format_name()) != "openexr" || fileSpec.tile_width > 0 ||
        fileSpec.deep || first->current_subimage() != 0)
        return readWhole(path, image, chbegin, chend, error);

    chbegin = std::clamp(chbegin, 0, fileSpec.nchannels);
    chend = std::clamp(chend, chbegin, fileSpec.nchannels);
    OIIO::ImageSpec spec = fileSpec;
    spec.nchannels = chend - chbegin;
    spec.channelnames.assign(fileSpec.channelnames.begin() + chbegin,
                             fileSpec.channelnames.begin() + chend);
    spec.channelformats.clear();
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.alpha_channel = fileSpec.alpha_channel - chbegin;
    if (spec.alpha_channel < 0 || spec.alpha_channel >= spec.nchannels) spec.alpha_channel = -1;
    spec.z_channel = fileSpec.z_channel - chbegin;
    if (spec.z_channel < 0 || spec.z_channel >= spec.nchannels) spec.z_channel = -1;
    const OIIO::ImageSpec& held = image.spec();
    if (image.initialized() && image.localpixels() && held.format == OIIO::TypeDesc::FLOAT &&
        held.channelformats.empty() && held.x == spec.x && held.y == spec.y &&
        held.width == spec.width && held.height == spec.height && held.nchannels == spec.nchannels)
        image.specmod() = spec;
    else
        image.reset(spec, OIIO::InitializePixels::No);

    const int rows = bandRows(fileSpec);
    const int bands = (spec.height + rows - 1) / rows;
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    const int workers = std::clamp(nthreads > 0 ? nthreads : cores, 1, std::max(1, bands));
    // Each band is read in the file's own types into a buffer of the worker's and converted
    // here: ImageInput::read_scanlines with a conversion maps (and page-faults) a fresh buffer
    // the size of the whole image on every call.
    const NativePixel native(fileSpec, chbegin, chend);
    std::atomic<int> next{0};
    std::atomic<bool> failed{false};
    std::mutex errorMutex;
    auto work = [&](std::unique_ptr<OIIO::ImageInput> in) {
        if (!in) in = OIIO::ImageInput::open(path);
        std::vector<std::byte> band(size_t(rows) * size_t(spec.width) * native.bytes);
        for (int b = next++; b < bands && !failed; b = next++) {
            const int y0 = spec.y + b * rows, y1 = std::min(y0 + rows, spec.y + spec.height);
            const bool read =
                in && in->read_native_scanlines(0, 0, y0, y1, 0, chbegin, chend, band.data()) &&
                native.toFloat(band.data(), static_cast<float*>(image.pixeladdr(spec.x, y0)),
                               spec.width, y1 - y0);
            if (!read) {
                std::lock_guard<std::mutex> lock(errorMutex);
                if (!failed.exchange(true)) error = in ? in->geterror() : OIIO::geterror();
                return;
            }
        }
    };
    std::vector<std::thread> helpers;
    for (int t = 1; t < workers; ++t)
        helpers.emplace_back(work, nullptr);
    work(std::move(first));
    for (std::thread& t : helpers)
        t.join();
    if (failed) {
        image.reset();
        return false;
    }
    return true;
}

} // namespace dhdr::app
