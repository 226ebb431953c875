#include <dhdr/io/motion_channels.h>

namespace dhdr {

namespace {

bool endsWith(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

} // namespace

MotionChannels findMotionChannels(const OIIO::ImageSpec& spec) {
    MotionChannels m;
    const std::vector<std::string>& names = spec.channelnames;
    for (size_t c = 0; c + 3 < names.size() && m.motion < 0; ++c) {
        const std::string& name = names[c];
        if (name != "motion.X" && name != "Vector.X" && !endsWith(name, ".Vector.X")) continue;
        const std::string base = name.substr(0, name.size() - 1);
        if (names[c + 1] == base + "Y" && names[c + 2] == base + "Z" &&
            names[c + 3] == base + "W") {
            m.motion = int(c);
            m.motionName = name;
        }
    }
    for (size_t c = 0; c < names.size() && m.depth < 0; ++c) {
        const std::string& name = names[c];
        if (name == "Z" || name == "Depth.Z" || endsWith(name, ".Depth.Z")) {
            m.depth = int(c);
            m.depthName = name;
        }
    }
    return m;
}

} // namespace dhdr
