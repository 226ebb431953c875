#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <dhdr/tonemap/sanitize.h>
#include <vector>

namespace dhdr {

NonFiniteCount replaceNonFinite(OIIO::ImageBuf& img, OIIO::ROI roi, int nthreads,
                                bool zeroNegative) {
    NonFiniteCount count;
    if (!img.initialized() || img.spec().format != OIIO::TypeDesc::FLOAT || !img.localpixels())
        return count;
    if (!roi.defined()) roi = img.roi();
    roi = OIIO::roi_intersection(roi, img.roi());
    const int nch = img.nchannels();

    // Pass 1: per row, the counts and each channel's largest finite value.
    struct Row {
        NonFiniteCount count;
        std::vector<float> maxFinite;
    };
    std::vector<Row> rows(static_cast<size_t>(roi.height()));
    // f(pixel) for the pixels of row y from r.xbegin to r.xend.
    auto forEachPixel = [&](const OIIO::ROI& r, int y, auto&& f) {
        float* p = static_cast<float*>(img.pixeladdr(r.xbegin, y));
        for (int x = r.xbegin; x < r.xend; ++x, p += nch)
            f(p);
    };
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y) {
            Row& row = rows[size_t(y - roi.ybegin)];
            row.maxFinite.assign(size_t(nch), 0.0f);
            forEachPixel(r, y, [&](const float* p) {
                for (int c = roi.chbegin; c < roi.chend; ++c) {
                    if (std::isnan(p[c]))
                        ++row.count.nan;
                    else if (std::isinf(p[c]))
                        ++(p[c] > 0 ? row.count.positiveInf : row.count.negativeInf);
                    else if (zeroNegative && p[c] < 0.0f)
                        ++row.count.negative;
                    else
                        row.maxFinite[size_t(c)] = std::max(row.maxFinite[size_t(c)], p[c]);
                }
            });
        }
    });
    std::vector<float> maxFinite(size_t(nch), 0.0f);
    for (const Row& row : rows) {
        count.nan += row.count.nan;
        count.positiveInf += row.count.positiveInf;
        count.negativeInf += row.count.negativeInf;
        count.negative += row.count.negative;
        for (int c = 0; c < nch; ++c)
            maxFinite[size_t(c)] = std::max(maxFinite[size_t(c)], row.maxFinite[size_t(c)]);
    }
    if (count.total() == 0) return count;

    // Pass 2: replace.
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y)
            forEachPixel(r, y, [&](float* p) {
                for (int c = roi.chbegin; c < roi.chend; ++c) {
                    if (std::isnan(p[c]) || p[c] == -INFINITY || (zeroNegative && p[c] < 0.0f))
                        p[c] = 0.0f;
                    else if (p[c] == INFINITY)
                        p[c] = maxFinite[size_t(c)];
                }
            });
    });
    return count;
}

} // namespace dhdr
