// The post stages that read a G-buffer's geometry: edge AA (normal and depth) and motion blur
// (motion and depth). Parameter names, defaults and ranges are dhdr-aa's and dhdr-motionblur's
// options, and the channels are found as those tools find them.
#include "py_ops.h"

#include <OpenImageIO/imagebufalgo.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/io/motion_channels.h>
#include <dhdr/tonemap/edge_aa.h>
#include <dhdr/tonemap/motion_blur.h>
#include <memory>
#include <pybind11/stl.h>
#include <string>
#include <vector>

namespace dhdr::python {

namespace {

// The normal (3 channels) or depth (1) as its own float image: an Image of that many channels
// as it is (no copy), or the channels `names` of `from` (src or a G-buffer) copied out; null
// when `from` lacks one.
std::shared_ptr<ImageView> geometry(const py::object& given, const Image* from,
                                    const std::vector<const char*>& names, const char* what) {
    auto out = std::make_shared<ImageView>();
    if (!given.is_none()) {
        Image storage;
        const Image& image = asImage(given, what, storage);
        if (image.spec().nchannels != int(names.size()))
            throw py::value_error(std::string(what) + ": expected " + std::to_string(names.size()) +
                                  " channel(s), got " + std::to_string(image.spec().nchannels));
        *out = view(image);
        return out;
    }
    std::vector<int> order;
    for (const char* n : names) {
        const int c = from->spec().channelindex(n);
        if (c < 0) return nullptr;
        order.push_back(c);
    }
    const ImageView v = view(*from);
    OIIO::ImageBufAlgo::channels(out->buf, v.buf, int(order.size()), order.data());
    out->buf.set_origin(v.buf.spec().x, v.buf.spec().y);
    return out;
}

// The motion channels (4) or the depth channel of `image`, as dhdr-motionblur finds them
// (findMotionChannels: motion.X … W or Blender's <layer>.Vector.X … W; Z, Depth.Z or
// <layer>.Depth.Z); empty when absent.
std::vector<const char*> motionNames(const Image& image, std::vector<std::string>& storage,
                                     bool depth) {
    const std::vector<std::string>& names = image.spec().channelnames;
    const MotionChannels found = findMotionChannels(image.spec());
    storage.clear();
    if (depth && found.depth >= 0) storage = {names[size_t(found.depth)]};
    if (!depth && found.motion >= 0)
        storage.assign(names.begin() + found.motion, names.begin() + found.motion + 4);
    std::vector<const char*> out;
    for (const std::string& n : storage)
        out.push_back(n.c_str());
    return out;
}

ImageOp motionBlurOp(const Image& src, const py::object& motion, const py::object& depth,
                     const py::object& gbuffer, float shutter, int samples, int maxBlur,
                     float depthSoftness) {
    MotionBlurParams p;
    p.shutter = shutter;
    p.samples = samples;
    p.maxBlur = maxBlur;
    p.depthSoftness = depthSoftness;
    checkParams(p, kMotionBlurFloatTable);
    checkParams(p, kMotionBlurIntTable);
    // Like dhdr-motionblur: the motion and depth of --gbuffer, else the image's own channels.
    Image gstorage;
    const Image* from = gbuffer.is_none() ? &src : &asImage(gbuffer, "gbuffer", gstorage);
    const char* source = gbuffer.is_none() ? "src" : "gbuffer";
    std::vector<std::string> mstore, zstore;
    const std::vector<const char*> motionChannels = motionNames(*from, mstore, false);
    if (motion.is_none() && motionChannels.empty())
        throw py::value_error(std::string(source) +
                              ": no motion channels (motion.X motion.Y motion.Z motion.W, or "
                              "Blender's Vector pass) — give motion= or gbuffer=");
    const std::vector<const char*> depthChannels = motionNames(*from, zstore, true);
    if (depth.is_none() && depthChannels.empty())
        throw py::value_error(std::string(source) +
                              ": no depth channel (Z, or Blender's Depth.Z) — give depth= or "
                              "gbuffer=");
    // Given arrays: 4 and 1 channels (geometry checks the counts).
    const std::shared_ptr<ImageView> M = geometry(
        motion, from,
        motion.is_none() ? motionChannels : std::vector<const char*>{"X", "Y", "Z", "W"}, "motion");
    const std::shared_ptr<ImageView> Z = geometry(
        depth, from, depth.is_none() ? depthChannels : std::vector<const char*>{"Z"}, "depth");
    // dhdr-motionblur blurs the colour (R, G, B and A) and copies every other channel.
    const int colour = src.spec().alpha_channel == 3 ? 4 : 3;
    return [p, M, Z, colour](OIIO::ImageBuf& dst, const OIIO::ImageBuf& s, OIIO::ROI roi, int n) {
        if (!roi.defined()) {
            roi = s.roi();
            roi.chend = colour;
        }
        return motionBlur(dst, s, M->buf, Z->buf, p, roi, n);
    };
}

ImageOp edgeAAOp(const Image& src, const py::object& normal, const py::object& depth,
                 const py::object& gbuffer, const std::string& use, float normalWeight,
                 float depthWeight, float maxOffset) {
    if (use != "normal" && use != "depth" && use != "both")
        throw py::value_error("use must be normal, depth or both, got '" + use + "'");
    EdgeAAParams p;
    p.normalWeight = normalWeight;
    p.depthWeight = depthWeight;
    p.maxOffset = maxOffset;
    checkParams(p, kEdgeAAFloatTable);
    // Like dhdr-aa: the geometry of --gbuffer, else the image's own N.* and Z channels.
    Image gstorage;
    const Image* from = gbuffer.is_none() ? &src : &asImage(gbuffer, "gbuffer", gstorage);
    const char* source = gbuffer.is_none() ? "src" : "gbuffer";
    std::shared_ptr<ImageView> N, Z;
    if (use != "depth") {
        N = geometry(normal, from, {gbuffer::kNormal[0], gbuffer::kNormal[1], gbuffer::kNormal[2]},
                     "normal");
        if (!N)
            throw py::value_error(std::string(source) +
                                  ": no channel 'N.X' — give normal= or gbuffer=");
    }
    if (use != "normal") {
        Z = geometry(depth, from, {gbuffer::kDepth}, "depth");
        if (!Z)
            throw py::value_error(std::string(source) +
                                  ": no channel 'Z' — give depth= or gbuffer=");
    }
    // dhdr-aa filters the colour (R, G, B and A) and copies every other channel.
    const int colour = src.spec().alpha_channel == 3 ? 4 : 3;
    return [p, N, Z, colour](OIIO::ImageBuf& dst, const OIIO::ImageBuf& s, OIIO::ROI roi, int n) {
        if (!roi.defined()) {
            roi = s.roi();
            roi.chend = colour;
        }
        return edgeAA(dst, s, N ? &N->buf : nullptr, Z ? &Z->buf : nullptr, p, roi, n);
    };
}

} // namespace

void bindGeometryOps(py::module_& m) {
    defImageOp(m, "edge_aa", R"(Edge-detect anti-aliasing (dhdr-aa): a blur factor from the squared
differences of normal and depth to the 8 neighbours; where it is above zero the pixel is
resampled at neighbour offsets scaled by it (max_offset pixels at full blur), elsewhere
copied bit for bit. normal (3 channels) and depth (1) are images of src's size; without them
they come from gbuffer= (an Image with N.X N.Y N.Z and Z), else from src's own channels.
use: 'normal', 'depth' or 'both'. R, G, B (A) are filtered, other channels copied.)",
               &edgeAAOp, py::kw_only(), py::arg("normal") = py::none(),
               py::arg("depth") = py::none(), py::arg("gbuffer") = py::none(),
               py::arg("use") = "both", py::arg("normal_weight") = EdgeAAParams{}.normalWeight,
               py::arg("depth_weight") = EdgeAAParams{}.depthWeight,
               py::arg("max_offset") = EdgeAAParams{}.maxOffset);

    defImageOp(
        m, "motion_blur", R"(Motion blur in linear HDR (dhdr-motionblur; McGuire et al. 2012's
reconstruction filter): each pixel gathers taps along the longest motion of its neighbourhood,
weighted by depth so that what is in front streaks over what is behind. motion (4 channels:
X, Y = previous - now, Z, W = now - next, pixels, y up, Blender's Vector convention) and depth
(1) are images of src's size; without them they come from gbuffer= (motion.X..W or
<layer>.Vector.X..W, and Z or Depth.Z), else from src's own channels. shutter: in frames,
centred; samples: taps; max_blur: pixels from a pixel to the end of its streak;
depth_softness: relative (their defaults and ranges: dhdr-motionblur --help). R, G, B (A) are
blurred, other channels copied; pixels with no motion nearby are copied bit for bit.)",
        &motionBlurOp, py::kw_only(), py::arg("motion") = py::none(), py::arg("depth") = py::none(),
        py::arg("gbuffer") = py::none(), py::arg("shutter") = MotionBlurParams{}.shutter,
        py::arg("samples") = MotionBlurParams{}.samples,
        py::arg("max_blur") = MotionBlurParams{}.maxBlur,
        py::arg("depth_softness") = MotionBlurParams{}.depthSoftness);
}

} // namespace dhdr::python
