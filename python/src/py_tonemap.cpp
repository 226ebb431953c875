// The tone-map stage's operations (libtonemap): metering, every tone-map operator, eye
// adaptation, bloom, the OCIO display transform and quantization. Parameter names, defaults
// and ranges are dhdr-tonemap's and dhdr-bloom's options.
#include "py_ops.h"

#include <OpenImageIO/imagebufalgo.h>
#include <cmath>
#include <dhdr/io/sanitize.h>
#include <dhdr/tonemap/adaptation.h>
#include <dhdr/tonemap/bloom.h>
#include <dhdr/tonemap/display_transform.h>
#include <dhdr/tonemap/frame_recipe.h>
#include <dhdr/tonemap/metering.h>
#include <dhdr/tonemap/tone_map.h>
#include <memory>
#include <optional>
#include <pybind11/stl.h>

namespace dhdr::python {

namespace {

using namespace pybind11::literals;
using Percentiles = std::pair<double, double>;

// `src`, or a (height, width) array's one channel as grey R = G = B in `grey`: the calls on
// colour take what the docs promise them.
const OIIO::ImageBuf& colourOf(const OIIO::ImageBuf& src, OIIO::ImageBuf& grey, int nthreads) {
    if (src.nchannels() != 1) return src;
    const int order[] = {0, 0, 0};
    const std::string names[] = {"R", "G", "B"};
    OIIO::ImageBufAlgo::channels(grey, src, 3, order, {}, names, false, nthreads);
    return grey;
}

LuminanceStatsParams luminanceParams(const std::string& weights, double delta, bool skip) {
    LuminanceStatsParams p;
    if (weights == "seed")
        p.weights = kSeedLuminanceWeights;
    else if (weights == "rec709")
        p.weights = kRec709LuminanceWeights;
    else
        throw py::value_error("weights must be seed or rec709, got '" + weights + "'");
    p.delta = delta;
    checkParams(p, kLuminanceFloatTable);
    p.skipTransparent = skip;
    return p;
}

MeteringParams meteringParams(const std::string& metering, Percentiles window,
                              const std::string& weights, double delta, bool skip) {
    MeteringParams p;
    if (metering == "histogram")
        p.mode = MeteringMode::Histogram;
    else if (metering != "log-average")
        throw py::value_error("metering must be log-average or histogram, got '" + metering + "'");
    p.lowPercentile = window.first;
    p.highPercentile = window.second;
    if (const std::string e = percentilesProblem(p, Spelling::Keyword); !e.empty())
        throw py::value_error(e);
    p.luminance = luminanceParams(weights, delta, skip);
    return p;
}

// The metering keyword arguments every metering call takes, with dhdr-tonemap's defaults.
#define DHDR_METERING_ARGS                                                                         \
    py::arg("metering") = "log-average", py::arg("percentiles") = Percentiles{5.0, 95.0},          \
    py::arg("weights") = "seed", py::arg("delta") = LuminanceStatsParams{}.delta,                  \
    py::arg("skip_transparent") = true

// tone_map's keywords as dhdr-tonemap's --op, --key, --exposure, --white, the metering
// options, --phi, --epsilon and --drago-bias.
ToneMapParams toneMapParams(const std::string& op, double key, double exposure,
                            const py::object& white, const std::string& metering,
                            Percentiles window, const std::string& weights, double delta, bool skip,
                            double phi, double epsilon, double dragoBias) {
    ToneMapParams p;
    if (std::string error; !setChoice(kToneMapChoiceTable[0], p, op, Spelling::Keyword, error))
        throw py::value_error(error);
    p.key = key;
    p.exposure = exposure;
    p.phi = phi;
    p.epsilon = epsilon;
    p.dragoBias = dragoBias;
    checkParams(p, kToneMapFloatTable);
    // "auto" (the largest), "inf", or a positive number, as --white; a number as Python
    // spells it (repr: 'inf', 'nan', '1e-05').
    const std::string w = py::isinstance<py::str>(white)
                              ? white.cast<std::string>()
                              : py::repr(py::float_(white)).cast<std::string>();
    if (std::string error; !parseWhite(w, p.white, Spelling::Keyword, error))
        throw py::value_error(error);
    p.metering = meteringParams(metering, window, weights, delta, skip);
    return p;
}

ImageOp toneMapOp(const Image&, const std::string& op, double key, double exposure,
                  const py::object& white, const std::string& metering, Percentiles window,
                  const std::string& weights, double delta, bool skip,
                  std::optional<LuminanceStats> stats, double phi, double epsilon,
                  double dragoBias) {
    const ToneMapParams p = toneMapParams(op, key, exposure, white, metering, window, weights,
                                          delta, skip, phi, epsilon, dragoBias);
    std::shared_ptr<LuminanceStats> given;
    if (stats) given = std::make_shared<LuminanceStats>(*stats);
    return [p, given](OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi, int n) {
        ToneMapParams q = p;
        q.stats = given.get();
        OIIO::ImageBuf grey;
        return toneMap(dst, colourOf(src, grey, n), q, roi, n);
    };
}

BloomParams bloomParams(float threshold, float key, float sigma, float strength,
                        const std::string& weights, double delta, bool skip) {
    BloomParams p;
    p.threshold = threshold;
    p.key = key;
    p.sigma = sigma;
    p.strength = strength;
    checkParams(p, kBloomFloatTable);
    p.metering = luminanceParams(weights, delta, skip);
    return p;
}

#define DHDR_BLOOM_ARGS                                                                            \
    py::arg("threshold") = BloomParams{}.threshold, py::arg("key") = BloomParams{}.key,            \
    py::arg("sigma") = BloomParams{}.sigma, py::arg("strength") = BloomParams{}.strength,          \
    py::arg("weights") = "seed", py::arg("delta") = LuminanceStatsParams{}.delta,                  \
    py::arg("skip_transparent") = true

ImageOp bloomOp(const Image&, float threshold, float key, float sigma, float strength,
                const std::string& weights, double delta, bool skip) {
    const BloomParams p = bloomParams(threshold, key, sigma, strength, weights, delta, skip);
    return [p](OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, OIIO::ROI roi, int n) {
        OIIO::ImageBuf grey;
        return bloom(dst, colourOf(src, grey, n), p, roi, n);
    };
}

std::shared_ptr<DisplayTransform>
displayTransform(const std::string& config, const std::string& colorspace,
                 const std::string& display, const std::string& view, const std::string& look) {
    auto t = std::make_shared<DisplayTransform>();
    std::string error;
    if (!t->init({config, colorspace, display, view, look}, error)) throw py::value_error(error);
    return t;
}

#define DHDR_DISPLAY_ARGS                                                                          \
    py::arg("config") = "", py::arg("colorspace") = "", py::arg("display") = "",                   \
    py::arg("view") = "", py::arg("look") = ""

// In place on a copy of src (dst's own pixels in the dst form): OCIO works on float in memory.
ImageOp colourOp(std::shared_ptr<DisplayTransform> t, bool toDisplay) {
    return [t, toDisplay](OIIO::ImageBuf& dst, const OIIO::ImageBuf& given, OIIO::ROI roi, int n) {
        OIIO::ImageBuf grey;
        const OIIO::ImageBuf& src = colourOf(given, grey, n);
        const bool copied = dst.initialized()
                                ? OIIO::ImageBufAlgo::copy(dst, src, OIIO::TypeUnknown, roi, n)
                                : dst.copy(src, OIIO::TypeDesc::FLOAT);
        if (!copied) return false;
        if (toDisplay ? t->toDisplay(dst, roi, n) : t->toSceneLinear(dst, roi, n)) return true;
        dst.errorfmt("the display transform needs float pixels in memory");
        return false;
    };
}

ImageOp toDisplayOp(const Image&, const std::string& config, const std::string& colorspace,
                    const std::string& display, const std::string& view, const std::string& look) {
    return colourOp(displayTransform(config, colorspace, display, view, look), true);
}

ImageOp toSceneLinearOp(const Image&, const std::string& config, const std::string& colorspace,
                        const std::string& display, const std::string& view,
                        const std::string& look) {
    return colourOp(displayTransform(config, colorspace, display, view, look), false);
}

LuminanceStats meterImage(const Image& given, const MeteringParams& p, OIIO::ROI roi, int nthreads,
                          const char* what) {
    Image finite;
    const Image& image = finiteImage(given, what, finite);
    const ImageView v = view(image);
    LuminanceStats stats;
    bool ok = false;
    {
        py::gil_scoped_release gil;
        OIIO::ImageBuf grey;
        ok = meter(stats, colourOf(v.buf, grey, nthreads), p, roi, nthreads);
    }
    if (!ok)
        raiseError("cannot meter an image of " + std::to_string(image.spec().nchannels) +
                   " channels (R, G, B needed)");
    return stats;
}

// dhdr-tonemap's reading of a frame (prepareFrame), on a copy of src.
Image prepareFrameOf(const py::object& src, const std::string& config,
                     const std::string& colorspace, int nthreads) {
    Image storage;
    const Image& image = asImage(src, "src", storage);
    const std::shared_ptr<DisplayTransform> t = displayTransform(config, colorspace, "", "", "");
    return runNew(image, {}, nthreads,
                  [t](OIIO::ImageBuf& dst, const OIIO::ImageBuf& s, OIIO::ROI roi, int n) {
                      OIIO::ImageBuf grey;
                      return prepareFrame(dst, colourOf(s, grey, n), *t, nullptr, roi, n);
                  });
}

// dhdr-tonemap on one frame in memory (the frame recipe): prepared as the tool reads it,
// tone-mapped, encoded for the display; at most R, G, B, A, as floats or with `bits`
// quantized into an integer array.
// `reading`: the transform of prepare_frame.
py::object tonemapFrame(const Image& image, const DisplayTransform& reading,
                        const ToneMapParams& tone, const std::optional<LuminanceStats>& stats,
                        const std::string& config, const std::string& colorspace,
                        const std::string& display, const std::string& view,
                        const std::string& look, const py::object& bits, bool dither,
                        int nthreads) {
    // The display's transform (op='aces' defaults the view to ACES, as --op aces does).
    const auto shown =
        displayTransform(config, colorspace, display,
                         view.empty() && tone.op == ToneOperator::Aces ? "ACES" : view, look);
    FrameRecipe recipe;
    recipe.toneMap = tone;
    recipe.toneMap.stats = stats ? &*stats : nullptr;
    recipe.display = shown.get();
    recipe.dither = dither;
    const int nbits = bits.is_none() ? 0 : bits.cast<int>();
    if (nbits != 0 && nbits != 8 && nbits != 16)
        throw py::value_error("bits: " + std::to_string(nbits) + " is not 8 or 16");
    recipe.type = nbits == 8    ? OIIO::TypeDesc::UINT8
                  : nbits == 16 ? OIIO::TypeDesc::UINT16
                                : OIIO::TypeDesc::FLOAT;
    const ImageView in = python::view(image);
    OIIO::ImageBuf grey;
    const OIIO::ImageBuf& colour = colourOf(in.buf, grey, nthreads);
    // The frame's own channel names and metadata on the first four channels.
    OIIO::ImageSpec spec = colour.spec();
    spec.nchannels = std::min(spec.nchannels, 4);
    spec.channelnames.resize(size_t(spec.nchannels));
    spec.channelformats.clear();
    if (spec.alpha_channel >= spec.nchannels) spec.alpha_channel = -1;
    if (spec.z_channel >= spec.nchannels) spec.z_channel = -1;
    spec.set_format(recipe.type);
    const std::vector<py::ssize_t> shape = {spec.height, spec.width, spec.nchannels};
    py::array quantized;
    if (nbits == 8) quantized = py::array_t<uint8_t>(shape);
    if (nbits == 16) quantized = py::array_t<uint16_t>(shape);
    OIIO::ImageBuf out =
        nbits ? OIIO::ImageBuf(spec, quantized.mutable_data()) : OIIO::ImageBuf(spec);
    OIIO::ImageBuf prepared;
    bool ok = false;
    {
        py::gil_scoped_release gil;
        ok = prepareFrame(prepared, colour, reading, nullptr, {}, nthreads) &&
             toneMapFrame(out, prepared, recipe, {}, nthreads);
    }
    if (!ok) raiseError(out.has_error() ? out.geterror() : prepared.geterror());
    if (nbits) return std::move(quantized);
    return py::cast(Image::fromBuf(std::move(out)));
}

// The metering: LuminanceStats, meter, eye adaptation (dhdr-tonemap --metering, --adapt).
void bindMetering(py::module_& m) {
    py::class_<LuminanceStats>(m, "LuminanceStats",
                               "A frame's metered luminance (dhdr.meter), or the one a tone map "
                               "uses (tone_map(stats=...)).")
        .def(py::init([](double logAverage, double maxL, double minL, long long pixels) {
                 LuminanceStats s;
                 s.logAverage = logAverage;
                 s.maxLuminance = maxL;
                 s.minLuminance = minL;
                 s.pixels = pixels;
                 return s;
             }),
             py::kw_only(), "log_average"_a, "max_luminance"_a = 0.0, "min_luminance"_a = 0.0,
             "pixels"_a = 0)
        .def_readwrite("log_average", &LuminanceStats::logAverage)
        .def_readwrite("max_luminance", &LuminanceStats::maxLuminance)
        .def_readwrite("min_luminance", &LuminanceStats::minLuminance)
        .def_readwrite("pixels", &LuminanceStats::pixels)
        .def_readonly("negative_pixels", &LuminanceStats::negativePixels)
        .def_readonly("non_finite_pixels", &LuminanceStats::nonFinitePixels)
        .def_readonly("transparent_pixels", &LuminanceStats::transparentPixels)
        .def("__repr__", [](const LuminanceStats& s) {
            char text[200];
            std::snprintf(text, sizeof text,
                          "dhdr.LuminanceStats(log_average=%.9g, max_luminance=%.9g, "
                          "pixels=%lld)",
                          s.logAverage, s.maxLuminance, s.pixels);
            return std::string(text);
        });

    m.def(
        "meter",
        [](const py::object& src, const std::string& metering, Percentiles window,
           const std::string& weights, double delta, bool skip, const py::object& roi,
           int nthreads) {
            Image storage;
            const Image& image = asImage(src, "src", storage);
            return meterImage(image, meteringParams(metering, window, weights, delta, skip),
                              toRoi(roi), nthreads, "src");
        },
        "src"_a, py::kw_only(), DHDR_METERING_ARGS, "roi"_a = py::none(), "nthreads"_a = 0,
        "The luminance statistics of src's R, G, B as dhdr-tonemap meters them (its --metering, "
        "--percentiles, --weights and --delta).");

    m.def(
        "adapt_luminance",
        [](const std::vector<double>& metered, double fps, double rate, double speed) {
            AdaptationParams p;
            p.fps = fps;
            p.rate = rate;
            p.speed = speed;
            checkParams(p, kAdaptationFloatTable);
            for (size_t i = 0; i < metered.size(); ++i)
                if (!std::isfinite(metered[i]))
                    throw py::value_error("metered[" + std::to_string(i) + "]: " +
                                          py::repr(py::float_(metered[i])).cast<std::string>() +
                                          " is not a finite luminance");
            return adaptLuminance(metered, p);
        },
        "metered"_a, py::kw_only(), "fps"_a = AdaptationParams{}.fps,
        "rate"_a = AdaptationParams{}.rate, "speed"_a = AdaptationParams{}.speed,
        "Eye adaptation over a sequence's metered luminances: adapted += (L - adapted)(1 - "
        "rate^(speed/fps)), starting adapted to the first.");

    m.def(
        "adapt",
        [](const std::vector<py::object>& frames, double fps, double rate, double speed,
           const std::string& metering, Percentiles window, const std::string& weights,
           double delta, bool skip, int nthreads) {
            AdaptationParams ap;
            ap.fps = fps;
            ap.rate = rate;
            ap.speed = speed;
            checkParams(ap, kAdaptationFloatTable);
            const MeteringParams p = meteringParams(metering, window, weights, delta, skip);
            std::vector<LuminanceStats> stats;
            std::vector<double> measured;
            for (size_t i = 0; i < frames.size(); ++i) {
                Image storage;
                const std::string what = "frames[" + std::to_string(i) + "]";
                stats.push_back(meterImage(asImage(frames[i], what.c_str(), storage), p, {},
                                           nthreads, what.c_str()));
                measured.push_back(stats.back().logAverage);
            }
            const std::vector<double> adapted = adaptLuminance(measured, ap);
            for (size_t i = 0; i < stats.size(); ++i)
                stats[i].logAverage = adapted[i];
            return stats;
        },
        "frames"_a, py::kw_only(), "fps"_a = AdaptationParams{}.fps,
        "rate"_a = AdaptationParams{}.rate, "speed"_a = AdaptationParams{}.speed,
        DHDR_METERING_ARGS, "nthreads"_a = 0,
        R"(Eye adaptation over a list of frames (dhdr-tonemap --adapt): each frame metered, the
luminances adapted in order; returns one LuminanceStats per frame to give tone_map(stats=...).)");
}

// The operators: tone_map (--op) and bloom (dhdr-bloom).
void bindOperators(py::module_& m) {
    defImageOp(m, "tone_map",
               R"(Tone-maps scene-linear RGB to display-linear RGB (dhdr-tonemap's --op).

Meters src (or uses stats=, e.g. an adapted luminance from dhdr.adapt) and maps it with
op: reinhard, reinhard-local, drago, hable, pbr-neutral, agx, exposure, aces
(metered exposure; the ACES view does the rest) or none (x 2^exposure, unclipped).
key: the metered luminance maps to it; exposure: stops; white: reinhard's white
point ('auto': the largest, 'inf', or a number); metering: 'log-average' or 'histogram'
(within percentiles); weights: 'seed' (0.27/0.67/0.06) or 'rec709'; delta: the
log-average's delta; skip_transparent: leave alpha-0 pixels out of the metering.
phi, epsilon: reinhard-local (--phi, --epsilon); drago_bias: drago (--drago-bias). Alpha and further channels are copied.
The result is display-linear; to_display() encodes it, quantize() makes integers.)",
               &toneMapOp, py::kw_only(), py::arg("op") = toneOperatorName(ToneMapParams{}.op),
               py::arg("key") = ToneMapParams{}.key, py::arg("exposure") = ToneMapParams{}.exposure,
               py::arg("white") = "auto", DHDR_METERING_ARGS, py::arg("stats") = py::none(),
               py::arg("phi") = ToneMapParams{}.phi, py::arg("epsilon") = ToneMapParams{}.epsilon,
               py::arg("drago_bias") = ToneMapParams{}.dragoBias);

    defImageOp(m, "bloom", R"(Bloom (dhdr-bloom): a bright pass on a quarter-size copy (pixels whose
tone-mapped luminance L/(1+L), L = key Lw / log-average, exceeds threshold), downsampled to
1/8, a separable Gaussian of sigma (1/8-size pixels), upsampled and added x strength to
R, G, B. Other channels are copied.)",
               &bloomOp, py::kw_only(), DHDR_BLOOM_ARGS);

    m.def(
        "bloom_layer",
        [](const py::object& src, float threshold, float key, float sigma, float strength,
           const std::string& weights, double delta, bool skip, int nthreads) {
            Image storage;
            const Image& image = asImage(src, "src", storage);
            const BloomParams p =
                bloomParams(threshold, key, sigma, strength, weights, delta, skip);
            return runNew(image, {}, nthreads,
                          [p](OIIO::ImageBuf& dst, const OIIO::ImageBuf& s, OIIO::ROI, int n) {
                              return bloomLayer(dst, s, p, n);
                          });
        },
        "src"_a, py::kw_only(), DHDR_BLOOM_ARGS, "nthreads"_a = 0,
        "The bloom layer alone (3 channels, src's size, before strength).");
}

// The display: OpenColorIO both ways (quantization: py_quantize.cpp).
void bindDisplay(py::module_& m) {
    defImageOp(m, "to_display", R"(Encodes display-linear (tone-mapped) RGB for a display through
OpenColorIO, as dhdr-tonemap does after its operator: look, view and display of config (empty:
$OCIO, else the built-in config with display sRGB, views Standard and ACES). Names a config
lacks raise ValueError listing the valid ones.)",
               &toDisplayOp, py::kw_only(), DHDR_DISPLAY_ARGS);
    defImageOp(m, "to_scene_linear", R"(From the input's colour space (colorspace=, or sRGB when
the image's oiio:ColorSpace says so) to scene-linear, as dhdr-tonemap does on reading.)",
               &toSceneLinearOp, py::kw_only(), DHDR_DISPLAY_ARGS);
    m.def(
        "describe_display",
        [](const std::string& config, const std::string& colorspace, const std::string& display,
           const std::string& view, const std::string& look) {
            const auto t = displayTransform(config, colorspace, display, view, look);
            return py::make_tuple(t->describe(), t->outputColorSpace());
        },
        py::kw_only(), DHDR_DISPLAY_ARGS,
        "(description, output colour space) of a display transform, as dhdr-tonemap -v says it.");
}

// What the tools do on reading, and dhdr-tonemap's frame recipe.
void bindFrames(py::module_& m) {
    m.def(
        "replace_non_finite",
        [](Image& image, bool zeroNegative, const py::object& roi, int nthreads) {
            if (!image.writeable()) throw py::value_error("image: its pixels are read-only");
            ImageView v = view(image);
            const OIIO::ROI region = toRoi(roi);
            NonFiniteCount n;
            {
                py::gil_scoped_release gil;
                n = replaceNonFinite(v.buf, region, nthreads, zeroNegative);
            }
            return py::dict("nan"_a = n.nan, "positive_inf"_a = n.positiveInf,
                            "negative_inf"_a = n.negativeInf, "negative"_a = n.negative);
        },
        "image"_a, py::kw_only(), "zero_negative"_a = false, "roi"_a = py::none(), "nthreads"_a = 0,
        R"(In place, as the tools do on reading: NaN and -Inf become 0, +Inf 65504, and with
zero_negative finite negatives 0 (dhdr-tonemap's colour). Returns the counts.)");

    m.def("prepare_frame", &prepareFrameOf, "src"_a, py::kw_only(), "config"_a = "",
          "colorspace"_a = "", "nthreads"_a = 0,
          R"(dhdr-tonemap's reading of a frame, on a copy of src (an Image as dhdr.read gives it):
non-finite and negative colour replaced (NaN, -Inf and negatives by 0, +Inf by 65504;
alpha's non-finite values too), then brought to scene-linear from colorspace (or sRGB
when the image says so: to_scene_linear). What the tool meters and maps.)");
    m.def(
        "tonemap_frame",
        [](const py::object& src, std::optional<LuminanceStats> stats, const std::string& config,
           const std::string& colorspace, const std::string& display, const std::string& view,
           const std::string& look, const py::object& bits, bool dither, int nthreads,
           const std::string& op, double key, double exposure, const py::object& white,
           const std::string& metering, Percentiles window, const std::string& weights,
           double delta, bool skip, double phi, double epsilon, double dragoBias) {
            Image storage;
            const Image& image = asImage(src, "src", storage);
            // In the order the steps check their keywords: the reading, the tone map, the
            // display, the quantization.
            const auto reading = displayTransform(config, colorspace, "", "", "");
            const ToneMapParams tone = toneMapParams(op, key, exposure, white, metering, window,
                                                     weights, delta, skip, phi, epsilon, dragoBias);
            return tonemapFrame(image, *reading, tone, stats, config, colorspace, display, view,
                                look, bits, dither, nthreads);
        },
        "src"_a, py::kw_only(), "stats"_a = py::none(), "config"_a = "", "colorspace"_a = "",
        "display"_a = "", "view"_a = "", "look"_a = "", "bits"_a = py::none(), "dither"_a = true,
        "nthreads"_a = 0, py::arg("op") = toneOperatorName(ToneMapParams{}.op),
        py::arg("key") = ToneMapParams{}.key, py::arg("exposure") = ToneMapParams{}.exposure,
        py::arg("white") = "auto", DHDR_METERING_ARGS, py::arg("phi") = ToneMapParams{}.phi,
        py::arg("epsilon") = ToneMapParams{}.epsilon,
        py::arg("drago_bias") = ToneMapParams{}.dragoBias,
        R"(dhdr-tonemap on one frame in memory: what the tool does between reading and writing
(libtonemap's frame recipe, frame_recipe.h). src (an Image as dhdr.read gives it, left
unchanged) is prepared as the tool reads it (prepare_frame), tone-mapped (tone_map's
keywords and stats, e.g. one of dhdr.adapt's), and encoded for the display (to_display;
op='aces' defaults the view to ACES, as --op aces does). With bits=8 or 16 the result is
quantize()'s integer array (what PNG and TIFF get; dither applies to 8 bits only, as in the
tool), else the float Image an EXR gets (at most R, G, B, A).)");
}

} // namespace

void bindTonemap(py::module_& m) {
    bindMetering(m);
    bindOperators(m);
    bindDisplay(m);
    bindFrames(m);
}

} // namespace dhdr::python
