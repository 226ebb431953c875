// Other renderers' passes as a G-buffer (docs/interop.md): a channel map says, for each of the
// contract's channels, where it comes from in someone else's EXR, so that dhdr-light can add
// lights to Blender's (or another renderer's) render passes.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <string>
#include <vector>

namespace dhdr {

// Where one contract quantity comes from.
struct ChannelSource {
    std::vector<std::string> channels; // 1 or 3 source channel names, in order; empty: none
    std::vector<std::string>
        fallback;          // channels to use when `channels` are missing (with a warning)
    float scale = 1.0f;    // multiplies the values
    bool zUp = false;      // a Z-up vector or point: (x, y, z) → (x, z, −y)
    float value = 0.0f;    // the constant used when neither is present
    bool required = false; // an error when neither is present
};

struct ChannelMap {
    std::string name;
    ChannelSource depth, position, normal, albedo, roughness, metallic, emission, coverage;
    // Motion vectors in Blender's Vector-pass convention (4 channels), which become the
    // G-buffer's motion layer (gbuffer::kMotion); none named: no motion layer, unless
    // `motionByName` finds one as dhdr-motionblur does (findMotionChannels).
    ChannelSource motion;
    bool motionByName = false;
    // A pixel is background when its depth is at least this (Blender writes 1e10 there).
    float backgroundDepth = 1e9f;
};

// The map of Blender's Cycles/EEVEE passes: ViewLayer.Depth.Z, ViewLayer.Position.* and
// ViewLayer.Normal.* (Z-up), the AOVs ViewLayer.BaseColor.* , ViewLayer.Roughness.X and
// ViewLayer.Metallic.X that a user adds for this, DiffCol as the albedo without them; the
// Vector pass, when there is one, as the motion layer.
ChannelMap blenderChannelMap();

// Parses a channel map file (JSON, docs/interop.md). False with `error` saying why.
bool readChannelMap(const std::string& path, ChannelMap& map, std::string& error);

// Builds a flat G-buffer of the contract's channels (A, Z, P, N, albedo, roughness, metallic,
// emission; then motion.X … W when the map finds motion, copied as they are, background
// pixels included) from `src` (float pixels in memory) by `map`; the camera matrices are not set
// (gbuffer::writeCamera). `warnings` says which fallbacks and constants were used. False with
// `error` naming a missing required channel.
bool importGBuffer(const OIIO::ImageBuf& src, const ChannelMap& map, OIIO::ImageBuf& dst,
                   std::vector<std::string>& warnings, std::string& error);

} // namespace dhdr
