// dhdr.Image: pixels as a (height, width, channels) float32 numpy array that owns them, and
// the rest of an OpenImageIO spec (channel names, origin, metadata). Library calls see the
// array's memory through an ImageBuf that wraps it, so no pixel is copied on the way in; an
// ImageBuf a call returns becomes the next array's memory, owned by a capsule.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <string>
#include <vector>

namespace dhdr::python {

namespace py = pybind11;

class Image {
public:
    Image() = default;
    // `pixels`: (height, width) or (height, width, channels), converted to C-contiguous
    // float32 (a copy only when it is not already). `channels`: names, default R, G, B, A….
    Image(const py::object& pixels, const std::vector<std::string>& channels,
          const char* what = "pixels");
    // `buf`'s pixels become the array's without a copy when they are float in its own memory.
    // Call with the GIL held.
    static Image fromBuf(OIIO::ImageBuf&& buf);

    // A default py::array_t is a 0-size array, never null; a constructed Image has pixels.
    bool empty() const { return !m_pixels || m_pixels.size() == 0; }
    const OIIO::ImageSpec& spec() const { return m_spec; }
    OIIO::ImageSpec& spec() { return m_spec; }
    const py::array_t<float>& pixels() const { return m_pixels; }
    // Replaces the pixels; the channel names stay when the count is the same.
    void setPixels(const py::object& pixels);
    void setChannels(const std::vector<std::string>& names);
    bool writeable() const { return !empty() && m_pixels.writeable(); }

    // The last error of an op(dst, …) form that returned False.
    std::string error;

private:
    py::array_t<float> m_pixels;
    OIIO::ImageSpec m_spec; // float, the array's size; channel names and metadata
};

// An Image's pixels seen as an ImageBuf for the length of a call: `keep` holds the array, so
// another Python thread replacing the Image's pixels while the GIL is released frees nothing.
struct ImageView {
    py::array_t<float> keep;
    OIIO::ImageBuf buf;
    const float* data = nullptr;
};
ImageView view(const Image& image);

// A dhdr.Image, or anything numpy turns into an array (converted as Image does). `what` names
// the argument in errors ("src: expected …"). The returned reference lives in `storage` when a
// conversion was needed.
const Image& asImage(const py::handle& object, const char* what, Image& storage);

// `image`, or when it holds NaN or ±Inf outside its depth (Z, ZBack) a copy in `storage` where
// they are replaced as the tools replace them on reading (NaN and -Inf by 0, +Inf by 65504),
// with a RuntimeWarning counting them: what a call that must not return NaN or Inf reads.
const Image& finiteImage(const Image& image, const char* what, Image& storage);

// roi=None (everything), a tuple (xbegin, xend, ybegin, yend[, chbegin, chend]), or any object
// with those attributes (OpenImageIO.ROI).
OIIO::ROI toRoi(const py::handle& roi);

// The ImageBuf's spec attributes as Python values: strings, numbers, matrices as 4x4 lists.
py::dict attributesOf(const OIIO::ImageSpec& spec);
void setAttribute(OIIO::ImageSpec& spec, const std::string& name, const py::handle& value);

// A RuntimeWarning (what a tool prints as a warning); raises when warnings are errors (-W error).
void warn(const std::string& message);

// ValueError, as the tools' usage error, when an image to write is named with a '?' (OpenImageIO
// would read what follows it as options: the file could never be read back).
void checkImageName(const std::string& path, const char* what);

// The library's message of a failed call as a Python exception.
[[noreturn]] void raiseError(const std::string& message);

void bindImage(py::module_& m);

} // namespace dhdr::python
