// A dhdr G-buffer rewritten as Blender writes its render passes (ViewLayer.<pass>.<channel>,
// Z up, depth 1e10 where nothing is, no camera matrices): what dhdr-light --channels blender
// reads, made from a frame whose answer is known.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <gtest/gtest.h>
#include <string>
#include <vector>

namespace dhdr::test {

// A Blender channel and the G-buffer channel it copies (scaled by `sign`: glTF's (x, y, z) is
// (x, −z, y) in Blender), or, with an empty source, the constant `sign`.
struct BlenderChannel {
    std::string name, source;
    float sign = 1.0f;
};

// Depth, Position and Normal, then `extra`, written to `out`.
inline void writeBlenderPasses(const OIIO::ImageBuf& g, const std::string& out,
                               const std::vector<BlenderChannel>& extra) {
    std::vector<BlenderChannel> channels = {
        {"ViewLayer.Depth.Z", "Z"},          {"ViewLayer.Position.X", "P.X"},
        {"ViewLayer.Position.Y", "P.Z", -1}, {"ViewLayer.Position.Z", "P.Y"},
        {"ViewLayer.Normal.X", "N.X"},       {"ViewLayer.Normal.Y", "N.Z", -1},
        {"ViewLayer.Normal.Z", "N.Y"}};
    channels.insert(channels.end(), extra.begin(), extra.end());
    const OIIO::ImageSpec& gs = g.spec();
    OIIO::ImageSpec spec(gs.width, gs.height, int(channels.size()), OIIO::TypeDesc::FLOAT);
    for (size_t i = 0; i < channels.size(); ++i)
        spec.channelnames[i] = channels[i].name;
    OIIO::ImageBuf b(spec);
    std::vector<float> v(channels.size());
    for (int y = 0; y < gs.height; ++y)
        for (int x = 0; x < gs.width; ++x) {
            const bool covered = g.getchannel(x, y, 0, gs.channelindex("A")) > 0.0f;
            for (size_t i = 0; i < channels.size(); ++i) {
                const BlenderChannel& c = channels[i];
                v[i] = c.source.empty() ? c.sign
                                        : c.sign * g.getchannel(x, y, 0, gs.channelindex(c.source));
                if (c.source == "Z" && !covered) v[i] = 1e10f;
            }
            b.setpixel(x, y, v.data());
        }
    ASSERT_TRUE(b.write(out));
}

} // namespace dhdr::test
