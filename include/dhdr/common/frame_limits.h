// Frame numbers every tool and the Python module accept (--frame, --frames), and how many one
// run may take: loops over them never overflow, and a typo cannot ask for billions of frames.
// dhdr-farm has the same limits (apps/dhdr-farm/dhdr_farm/frames.py).
#pragma once

namespace dhdr {

inline constexpr long long kMinFrame = -99999999, kMaxFrame = 999999999, kMaxFrameCount = 1000000;

} // namespace dhdr
