#include "native_pixels.h"

#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <dhdr/io/banded_read.h>
#include <dhdr/io/pixel_limit.h>
#include <limits>
#include <memory>
#include <mutex>
#include <thread>
#include <unistd.h>
#include <vector>

namespace dhdr {

namespace {

// Rows per band: a multiple of every OpenEXR compression's lines per chunk, so that no chunk
// is decoded twice (DWAB packs 256 lines, PIZ, B44 and DWAA 32, ZIP 16).
int bandRows(const OIIO::ImageSpec& spec) {
    return spec.get_string_attribute("compression") == "dwab" ? 256 : 64;
}

// A file OIIO converts as a whole: images of other formats, whose integer pixels are
// fractions of full scale, and tiled EXRs, read natively so that uint channels stay integers.
bool readWhole(OIIO::ImageInput& in, const std::string& path, OIIO::ImageBuf& image, int subimage,
               int chbegin, int chend, std::string& error) {
    const OIIO::ImageSpec& fileSpec = in.spec();
    if (std::string(in.format_name()) != "openexr") {
        image.reset(path);
        if (!image.read(subimage, 0, chbegin, chend, true, OIIO::TypeDesc::FLOAT)) {
            error = image.geterror();
            return false;
        }
        return true;
    }
    const NativeReader native(fileSpec, chbegin, chend);
    std::vector<std::byte> buffer(size_t(fileSpec.image_pixels()) * native.bytes);
    const OIIO::ImageSpec spec = floatChannelSpec(fileSpec, chbegin, chend);
    image.reset(spec, OIIO::InitializePixels::No);
    if (!image.localpixels()) {
        error = "cannot allocate memory for its pixels";
        image.reset();
        return false;
    }
    if (!in.read_image(subimage, 0, chbegin, chend, OIIO::TypeUnknown, buffer.data()) ||
        !native.toFloat(buffer.data(), static_cast<float*>(image.localpixels()), spec.width,
                        spec.height)) {
        error = in.geterror();
        image.reset();
        return false;
    }
    return true;
}

std::string gigabytes(double bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f GB", bytes / 1e9);
    return text;
}

} // namespace

std::unique_ptr<OIIO::ImageInput> openFlatPart(const std::string& path, int subimage,
                                               std::string& error) {
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
    if (!in) {
        error = OIIO::geterror();
        return nullptr;
    }
    if (subimage != 0 && !in->seek_subimage(subimage, 0)) {
        error = "has no part " + std::to_string(subimage);
        return nullptr;
    }
    // Before any pixel is read: an image over --max-pixels (maxPixels()).
    if (std::string e = pixelLimitError(in->spec().width, in->spec().height, in->spec().depth);
        !e.empty()) {
        error = std::move(e);
        return nullptr;
    }
    if (in->spec().deep) {
        error = "is a deep image (a list of samples per pixel); this tool takes flat images: "
                "flatten it first, e.g. oiiotool IN.exr --flatten -o FLAT.exr";
        return nullptr;
    }
    return in;
}

OIIO::ImageSpec floatChannelSpec(const OIIO::ImageSpec& file, int chbegin, int chend) {
    OIIO::ImageSpec spec = file;
    spec.nchannels = chend - chbegin;
    spec.channelnames.assign(file.channelnames.begin() + chbegin,
                             file.channelnames.begin() + chend);
    spec.channelformats.clear();
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.tile_width = spec.tile_height = spec.tile_depth = 0;
    spec.alpha_channel = file.alpha_channel - chbegin;
    if (spec.alpha_channel < 0 || spec.alpha_channel >= spec.nchannels) spec.alpha_channel = -1;
    spec.z_channel = file.z_channel - chbegin;
    if (spec.z_channel < 0 || spec.z_channel >= spec.nchannels) spec.z_channel = -1;
    return spec;
}

bool fitsInMemory(const OIIO::ImageSpec& spec, int channels, std::string& error) {
    const double bytes = double(spec.width) * double(spec.height) *
                         double(std::max(spec.depth, 1)) * double(channels) * sizeof(float);
    const double memory = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
    if (bytes <= memory) return true;
    error = "its " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
            " pixels of " + std::to_string(channels) + " channels need " + gigabytes(bytes) +
            " as float, more than this machine's " + gigabytes(memory) + " of memory";
    return false;
}

bool readBanded(const std::string& path, OIIO::ImageBuf& image, int chbegin, int chend,
                int nthreads, std::string& error, int subimage) {
    std::unique_ptr<OIIO::ImageInput> first = openFlatPart(path, subimage, error);
    if (!first) return false;
    const OIIO::ImageSpec& fileSpec = first->spec();
    chbegin = std::clamp(chbegin, 0, fileSpec.nchannels);
    chend = std::clamp(chend, chbegin, fileSpec.nchannels);
    if (!fitsInMemory(fileSpec, chend - chbegin, error)) return false;
    if (std::string(first->format_name()) != "openexr" || fileSpec.tile_width > 0)
        return readWhole(*first, path, image, subimage, chbegin, chend, error);

    const OIIO::ImageSpec spec = floatChannelSpec(fileSpec, chbegin, chend);
    const OIIO::ImageSpec& held = image.spec();
    if (image.initialized() && image.localpixels() && held.format == OIIO::TypeDesc::FLOAT &&
        held.channelformats.empty() && held.x == spec.x && held.y == spec.y &&
        held.width == spec.width && held.height == spec.height && held.nchannels == spec.nchannels)
        image.specmod() = spec;
    else
        image.reset(spec, OIIO::InitializePixels::No);
    if (!image.localpixels()) {
        error = "cannot allocate memory for its pixels";
        image.reset();
        return false;
    }

    const int rows = bandRows(fileSpec);
    const int bands = (spec.height + rows - 1) / rows;
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    const int workers = std::clamp(nthreads > 0 ? nthreads : cores, 1, std::max(1, bands));
    // Each band is read in the file's own types into a buffer of the worker's and converted
    // here: ImageInput::read_scanlines with a conversion maps (and page-faults) a fresh buffer
    // the size of the whole image on every call.
    const NativeReader native(fileSpec, chbegin, chend);
    std::atomic<int> next{0};
    std::atomic<bool> failed{false};
    std::mutex errorMutex;
    auto work = [&](std::unique_ptr<OIIO::ImageInput> in) {
        if (!in) {
            in = OIIO::ImageInput::open(path);
            if (in && subimage != 0 && !in->seek_subimage(subimage, 0)) in.reset();
        }
        std::vector<std::byte> band(size_t(rows) * size_t(spec.width) * native.bytes);
        for (int b = next++; b < bands && !failed; b = next++) {
            const int y0 = spec.y + b * rows, y1 = std::min(y0 + rows, spec.y + spec.height);
            const bool read =
                in &&
                in->read_native_scanlines(subimage, 0, y0, y1, 0, chbegin, chend, band.data()) &&
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

} // namespace dhdr
