// Motion blur in post, in linear HDR: McGuire, Hennessy, Bukowski & Osman 2012, "A
// reconstruction filter for plausible motion blur" (tile max velocity, neighbour max, depth-aware
// foreground/background weights), driven by a G-buffer's motion vectors.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <dhdr/common/param_table.h>
#include <glm/glm.hpp>
#include <string>

namespace dhdr {

struct MotionBlurParams {
    // Shutter, in frames, centred on the frame (Cycles' default 0.5); [0, 2]. 0: no blur.
    float shutter = 0.5f;
    // Taps along each pixel's blur; [1, 256]. The paper's 15 at its 1080p; 8 is cleaner than
    // it sounds, since the taps are jittered per pixel.
    int samples = 15;
    // Longest blur, pixels from a pixel to the end of its streak (half a streak), and the side
    // of the velocity tiles; [1, 128]. Longer motion is shortened to it.
    int maxBlur = 32;
    // Depth difference, relative to the nearer depth, over which one surface passes from
    // behind another to in front of it; (0, 1]. The paper's SOFT_Z_EXTENT, made relative so
    // that it means the same at any distance.
    float depthSoftness = 0.01f;
};

// MotionBlurParams' ranges, and the options of dhdr-motionblur and keywords of
// dhdr.motion_blur() that set them.
inline constexpr FloatParam<MotionBlurParams> kMotionBlurFloatTable[] = {
    {"--shutter",
     "shutter",
     &MotionBlurParams::shutter,
     {0.0, 2.0},
     "FRAMES",
     "shutter, in frames, centred on the frame, as Cycles'"},
    {"--depth-softness",
     "depth_softness",
     &MotionBlurParams::depthSoftness,
     {0.0, 1.0, true},
     "R",
     "relative depth difference over which a surface passes from behind another to in front"},
};
inline constexpr IntParam<MotionBlurParams> kMotionBlurIntTable[] = {
    {"--samples", &MotionBlurParams::samples, 1, 256, "N", "taps along each pixel's blur",
     "samples"},
    {"--max-blur", &MotionBlurParams::maxBlur, 1, 128, "PX",
     "longest blur, pixels from a pixel to the end of its streak (longer motion is shortened)",
     "max_blur"},
};

// The half-exposure blur vector of a pixel, in image pixels (x right, y down), from its motion
// in Blender's Vector-pass convention: X, Y = position at the previous frame − now, Z, W = now −
// position at the next frame, pixels, y up. The exposure moves the point from its position at
// −shutter / 2 to +shutter / 2 frames, at the mean velocity (next − previous) / 2.
inline glm::vec2 motionBlurVector(const float* motion, float shutter) {
    const float vx = -(motion[0] + motion[2]) * 0.5f, vyUp = -(motion[1] + motion[3]) * 0.5f;
    return glm::vec2(vx, -vyUp) * (0.5f * shutter);
}

// dst = src blurred along its motion over `roi` (default: src's pixels). `motion` holds 4
// channels (Blender's Vector convention, above) and `depth` one (distance or view depth, +∞ on
// the background), both over src's pixels. Every channel of src is filtered; where no motion
// within maxBlur × 2 pixels reaches half a pixel, the pixel is copied bit for bit, so a frame
// without motion is the input. A strip gives the whole frame's result for its rows when src,
// motion and depth hold motionBlurReach(params) rows above and below it. Per-pixel jitter is
// a hash of the pixel: the same result at any thread count.
bool motionBlur(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const OIIO::ImageBuf& motion,
                const OIIO::ImageBuf& depth, const MotionBlurParams& params = {},
                OIIO::ROI roi = {}, int nthreads = 0);

// The rows above and below a pixel that its result reads: the neighbouring velocity tiles
// (up to 2 × maxBlur) and the taps (up to maxBlur).
inline int motionBlurReach(const MotionBlurParams& params) {
    return 2 * params.maxBlur;
}

// Whether `params` are within their ranges; false with `error` naming the first that is not.
bool validate(const MotionBlurParams& params, std::string& error);

} // namespace dhdr
