#include "float_pixels.h"

#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <dhdr/tonemap/metering.h>
#include <mutex>
#include <vector>

namespace dhdr {

namespace {

constexpr int kBins = 4096;

} // namespace

MeteringAccumulator::MeteringAccumulator(const MeteringParams& params)
    : m_params(params), m_luminance(params.luminance) {}

bool MeteringAccumulator::needsAnotherPass() const {
    return m_params.mode == MeteringMode::Histogram && m_pass > 0 && m_pass < 3 &&
           m_stats.pixels > 0;
}

void MeteringAccumulator::endPass() {
    if (m_pass == 0) {
        m_stats = m_luminance.result();
        // Histogram of ln(δ + Lw) between the extremes.
        const LuminanceStatsParams& lp = m_params.luminance;
        m_lo = std::log(lp.delta + std::max(m_stats.minLuminance, 0.0));
        const double hi = std::log(lp.delta + m_stats.maxLuminance);
        m_binWidth = std::max(hi - m_lo, 1e-12) / kBins;
        m_histogram.assign(kBins, 0);
    } else if (m_pass == 1) {
        // The bins holding the two percentiles; whole bins between them are metered.
        auto binAt = [&](double percentile) {
            const long long target =
                (long long)std::floor(percentile / 100.0 * double(m_stats.pixels));
            long long seen = 0;
            for (int b = 0; b < kBins; ++b) {
                seen += m_histogram[size_t(b)];
                if (seen > target) return b;
            }
            return kBins - 1;
        };
        m_first = binAt(m_params.lowPercentile);
        m_last = binAt(m_params.highPercentile);
    } else if (m_pass == 2 && m_count > 0) {
        m_stats.logAverage = std::exp(m_sum / double(m_count));
    }
    ++m_pass;
}

bool MeteringAccumulator::add(const OIIO::ImageBuf& src, OIIO::ROI roi, int nthreads) {
    if (m_pass == 0) return m_luminance.add(src, roi, nthreads);
    if (!src.initialized() || src.nchannels() < 3) return false;
    if (!roi.defined()) roi = src.roi();
    roi = OIIO::roi_intersection(roi, src.roi());
    if (roi.npixels() == 0) return true;

    const LuminanceStatsParams& lp = m_params.luminance;
    const bool skipTransparent = lp.skipTransparent && src.nchannels() >= 4;
    const detail::FloatPixels pixels(src);
    // ln(δ + Lw) of a pixel that is metered, NaN for one that is not.
    auto logLuminance = [&](int x, int y) {
        const float* p = pixels.at(x, y);
        if (skipTransparent && p[3] == 0.0f) return double(NAN);
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            return double(NAN);
        return std::log(lp.delta + std::max(0.0, double(luminance(p[0], p[1], p[2], lp.weights))));
    };
    auto binOf = [&](double v) { return std::clamp(int((v - m_lo) / m_binWidth), 0, kBins - 1); };

    if (m_pass == 1) {
        // Bins are integers, so merging per-chunk histograms in any order gives the same counts.
        std::mutex merge;
        OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
            std::vector<long long> local(kBins, 0);
            for (int y = r.ybegin; y < r.yend; ++y)
                for (int x = r.xbegin; x < r.xend; ++x) {
                    const double v = logLuminance(x, y);
                    if (!std::isnan(v)) ++local[size_t(binOf(v))];
                }
            std::lock_guard<std::mutex> lock(merge);
            for (int b = 0; b < kBins; ++b)
                m_histogram[size_t(b)] += local[size_t(b)];
        });
        return true;
    }
    if (m_pass != 2) return true;
    struct Row {
        double sum = 0.0;
        long long count = 0;
    };
    std::vector<Row> rows(static_cast<size_t>(roi.height()));
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y) {
            Row& row = rows[size_t(y - roi.ybegin)];
            for (int x = r.xbegin; x < r.xend; ++x) {
                const double v = logLuminance(x, y);
                if (std::isnan(v)) continue;
                const int b = binOf(v);
                if (b < m_first || b > m_last) continue;
                row.sum += v;
                ++row.count;
            }
        }
    });
    // Row order, whatever the strips.
    for (const Row& row : rows) {
        m_sum += row.sum;
        m_count += row.count;
    }
    return true;
}

std::string percentilesProblem(const MeteringParams& params, Spelling spelling) {
    const double lo = params.lowPercentile, hi = params.highPercentile;
    if (lo >= 0.0 && lo < hi && hi <= 100.0) return {};
    return spelling == Spelling::Option ? "--percentiles must be LO,HI with 0 <= LO < HI <= 100"
                                        : "percentiles must be (LO, HI) with 0 <= LO < HI <= 100";
}

bool meter(LuminanceStats& stats, const OIIO::ImageBuf& src, const MeteringParams& params,
           OIIO::ROI roi, int nthreads) {
    MeteringAccumulator accumulator(params);
    do {
        if (!accumulator.add(src, roi, nthreads)) {
            stats = {};
            return false;
        }
        accumulator.endPass();
    } while (accumulator.needsAnotherPass());
    stats = accumulator.result();
    return true;
}

} // namespace dhdr
