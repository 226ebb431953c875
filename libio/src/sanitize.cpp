#include <OpenImageIO/imagebufalgo_util.h>
#include <algorithm>
#include <cmath>
#include <dhdr/io/sanitize.h>
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

    // One pass, each value on its own: the result does not depend on how the image is cut
    // into strips, tiles or threads. Counts per row, summed in row order.
    std::vector<NonFiniteCount> rows(static_cast<size_t>(roi.height()));
    OIIO::ImageBufAlgo::parallel_image(roi, OIIO::paropt(nthreads), [&](OIIO::ROI r) {
        for (int y = r.ybegin; y < r.yend; ++y) {
            NonFiniteCount& row = rows[size_t(y - roi.ybegin)];
            float* p = static_cast<float*>(img.pixeladdr(r.xbegin, y));
            for (int x = r.xbegin; x < r.xend; ++x, p += nch)
                for (int c = roi.chbegin; c < roi.chend; ++c) {
                    float& v = p[c];
                    if (std::isnan(v)) {
                        ++row.nan;
                        v = 0.0f;
                    } else if (v == INFINITY) {
                        ++row.positiveInf;
                        v = kInfinityReplacement;
                    } else if (v == -INFINITY) {
                        ++row.negativeInf;
                        v = 0.0f;
                    } else if (zeroNegative && v < 0.0f) {
                        ++row.negative;
                        v = 0.0f;
                    }
                }
        }
    });
    for (const NonFiniteCount& row : rows)
        count += row;
    return count;
}

} // namespace dhdr
