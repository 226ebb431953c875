// Finding motion vectors in a file someone else wrote, by channel name: dhdr's motion layer or
// Blender's Vector pass, which share one convention (X, Y = position at the previous frame −
// now, Z, W = now − position at the next frame, pixels, y up; docs/animation.md), and the depth
// beside them. One finder for every reader: dhdr-motionblur, dhdr-light --channels blender and
// the Python module.
#pragma once

#include <OpenImageIO/imageio.h>
#include <string>

namespace dhdr {

struct MotionChannels {
    int motion = -1;                   // the first of 4 consecutive channels X, Y, Z, W; −1: none
    int depth = -1;                    // −1: none
    std::string motionName, depthName; // the first motion channel's name, the depth's
};

// The first run of four channels named motion.X … motion.W, Vector.X … W or
// <layer>.Vector.X … W (Blender's, e.g. ViewLayer.Vector.X), in that order; and the first
// channel named Z, Depth.Z or <layer>.Depth.Z.
MotionChannels findMotionChannels(const OIIO::ImageSpec& spec);

} // namespace dhdr
