// Options for OpenImageIO's parallel_for over a few large items (rows, tiles, frames), and
// loops over rows of very different cost.
#pragma once

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <cstdint>

namespace dhdr {

// OpenImageIO's default paropt runs a range of fewer than 1024 items on one thread; rows of
// an image or frames of a sequence are few but each is much work, so split down to one item.
inline OIIO::paropt perItem(int nthreads) {
    return OIIO::paropt(nthreads, OIIO::paropt::SplitDir::Y, 1);
}

// Rows of a frame differ widely in cost (sky against lit surfaces, settled against unsettled
// pixels). OpenImageIO's parallel_for and parallel_image cut a range into two chunks a
// thread, so each loop ends with cores idle while one thread finishes its chunk; 64 bands,
// taken by whichever thread is free, keep them busy. A row's result must not depend on the
// band it falls in.
template <class Band>
void parallelBands(int64_t begin, int64_t end, int nthreads, Band&& band) {
    constexpr int64_t kBands = 64;
    const int64_t rows = std::max<int64_t>(1, (end - begin + kBands - 1) / kBands);
    OIIO::parallel_for_chunked(
        begin, end, rows, [&](int64_t b, int64_t e) { band(b, e); }, perItem(nthreads));
}

// parallelBands, one row at a time.
template <class Row>
void parallelRows(int64_t begin, int64_t end, int nthreads, Row&& row) {
    parallelBands(begin, end, nthreads, [&](int64_t b, int64_t e) {
        for (int64_t y = b; y < e; ++y)
            row(y);
    });
}

// parallelBands over the rows of `roi`, each band as an ROI of whole rows (for the
// ImageBufAlgo-style loops that parallel_image ran).
template <class Region>
void parallelImageRows(const OIIO::ROI& roi, int nthreads, Region&& region) {
    parallelBands(roi.ybegin, roi.yend, nthreads, [&](int64_t ybegin, int64_t yend) {
        OIIO::ROI band = roi;
        band.ybegin = int(ybegin);
        band.yend = int(yend);
        region(band);
    });
}

} // namespace dhdr
