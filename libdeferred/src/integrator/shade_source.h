// A G-buffer opened for the lighting pass (lighting.cpp): flat (a strip of a frame, or all of
// it) or deep, read through one view.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/gbuffer/shading_point.h>
#include <dhdr/deferred/lights/light_culling.h>

namespace dhdr {

struct ShadeSource {
    const OIIO::ImageSpec& spec; // its header and channels; size and place of its pixels
    OIIO::ROI roi;               // the pixels it holds
    const gbuffer::Layout& layout;
    const gbuffer::CameraInfo& camera;
    GBufferView view;
    DepthView depth;
};

} // namespace dhdr
