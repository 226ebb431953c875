// Options for OpenImageIO's parallel_for over a few large items (rows, tiles, frames).
#pragma once

#include <OpenImageIO/parallel.h>

namespace dhdr {

// OpenImageIO's default paropt runs a range of fewer than 1024 items on one thread; rows of
// an image or frames of a sequence are few but each is much work, so split down to one item.
inline OIIO::paropt perItem(int nthreads) {
    return OIIO::paropt(nthreads, OIIO::paropt::SplitDir::Y, 1);
}

} // namespace dhdr
