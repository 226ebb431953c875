#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <cmath>
#include <cstdlib>
#include <dhdr/tonemap/local_reinhard.h>
#include <dhdr/tonemap/reinhard.h>
#include <dhdr/tonemap/tone_map.h>
#include <functional>

namespace dhdr {

namespace {

using detail::mapColour;

} // namespace

bool parseToneOperator(const std::string& name, ToneOperator& op) {
    const int index = choiceIndex(kToneMapChoiceTable[0].names, name);
    if (index >= 0) op = ToneOperator(index);
    return index >= 0;
}

std::string toneOperatorName(ToneOperator op) {
    return choiceName(kToneMapChoiceTable[0].names, int(op));
}

bool parseWhite(const std::string& text, double& white, Spelling spelling, std::string& error) {
    if (text == "auto" || text == "inf") {
        white = text == "auto" ? 0.0 : INFINITY;
        return true;
    }
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (!text.empty() && *end == '\0' && v > 0.0 && std::isfinite(v)) {
        white = v;
        return true;
    }
    error = spelling == Spelling::Option
                ? "--white must be a positive number, auto or inf"
                : "white must be a positive number, 'auto' or 'inf', got '" + text + "'";
    return false;
}

bool toneMap(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const ToneMapParams& params,
             OIIO::ROI roi, int nthreads) {
    if (!src.initialized() || src.nchannels() < 3) {
        dst.errorfmt("tone mapping needs an image with at least three channels");
        return false;
    }
    const double gain = std::exp2(params.exposure);
    if (params.op == ToneOperator::Exposure) {
        return mapColour(dst, src, roi, nthreads, [&](const float* p, int, int) {
            return glm::clamp(glm::vec3(p[0], p[1], p[2]) * float(gain), 0.0f, 1.0f);
        });
    }
    if (params.op == ToneOperator::None) {
        // Scene-linear handed on as it is (but for the exposure): a config's own view tone-maps.
        return mapColour(dst, src, roi, nthreads, [&](const float* p, int, int) {
            return glm::vec3(p[0], p[1], p[2]) * float(gain);
        });
    }
    LuminanceStats measured;
    const LuminanceStats* stats = params.stats;
    if (!stats) {
        meter(measured, src, params.metering, {}, nthreads);
        stats = &measured;
    }
    const double logAverage = stats->logAverage > 0.0 ? stats->logAverage : 1.0;
    const double scale = gain * params.key / logAverage; // L = scale · Lw
    const LuminanceWeights w = params.metering.luminance.weights;
    auto Lw = [&](const float* p) { return double(luminance(p[0], p[1], p[2], w)); };
    // Colour × Ld / Lw.
    auto byLuminance = [](const float* p, double Lw, double Ld) {
        const float ratio = Lw > 0.0 ? float(Ld / Lw) : 0.0f;
        return glm::vec3(p[0], p[1], p[2]) * ratio;
    };

    switch (params.op) {
    case ToneOperator::Reinhard: {
        ReinhardParams rp;
        rp.key = params.key;
        rp.exposure = params.exposure;
        rp.white = params.white;
        rp.metering = params.metering.luminance;
        rp.stats = stats;
        return reinhard(dst, src, rp, roi, nthreads);
    }
    case ToneOperator::ReinhardLocal: {
        OIIO::ImageSpec spec(src.spec().width, src.spec().height, 1, OIIO::TypeDesc::FLOAT);
        spec.x = src.spec().x;
        spec.y = src.spec().y;
        OIIO::ImageBuf scaled(spec, OIIO::InitializePixels::No), mapped;
        const detail::FloatPixels in(src);
        OIIO::ImageBufAlgo::parallel_image(scaled.roi(), OIIO::paropt(nthreads), [&](OIIO::ROI r) {
            for (int y = r.ybegin; y < r.yend; ++y)
                for (int x = r.xbegin; x < r.xend; ++x)
                    *detail::floatPixel(scaled, x, y) =
                        float(scale * std::max(Lw(in.at(x, y)), 0.0));
        });
        LocalReinhardParams lp;
        lp.key = params.key;
        lp.phi = params.phi;
        lp.epsilon = params.epsilon;
        localReinhard(mapped, scaled, lp, nthreads);
        return mapColour(dst, src, roi, nthreads, [&](const float* p, int x, int y) {
            const float Ld = *static_cast<const float*>(mapped.pixeladdr(x, y));
            return byLuminance(p, Lw(p), Ld);
        });
    }
    case ToneOperator::Drago: {
        // World luminance in units of the metered adaptation luminance.
        const double Lwmax = std::max(scale * stats->maxLuminance, 1e-6);
        return mapColour(dst, src, roi, nthreads, [&](const float* p, int, int) {
            const double lw = Lw(p);
            return byLuminance(p, lw,
                               dragoCurve(scale * std::max(lw, 0.0), Lwmax, params.dragoBias));
        });
    }
    case ToneOperator::Hable:
        return mapColour(dst, src, roi, nthreads, [&](const float* p, int, int) {
            return glm::vec3(hable(float(scale * p[0]), params.hable),
                             hable(float(scale * p[1]), params.hable),
                             hable(float(scale * p[2]), params.hable));
        });
    case ToneOperator::PbrNeutral:
        return mapColour(dst, src, roi, nthreads, [&](const float* p, int, int) {
            return pbrNeutral(glm::max(glm::vec3(p[0], p[1], p[2]) * float(scale), 0.0f));
        });
    case ToneOperator::Agx:
        return mapColour(dst, src, roi, nthreads, [&](const float* p, int, int) {
            return agx(glm::vec3(p[0], p[1], p[2]) * float(scale));
        });
    case ToneOperator::Aces:
        // Scene-linear still: the ACES RRT and ODT follow as the display transform.
        return mapColour(dst, src, roi, nthreads, [&](const float* p, int, int) {
            return glm::vec3(p[0], p[1], p[2]) * float(scale);
        });
    case ToneOperator::Exposure:
    case ToneOperator::None:
        break;
    }
    return true;
}

} // namespace dhdr
