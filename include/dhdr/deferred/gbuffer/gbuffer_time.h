// Which moment of an animated scene a G-buffer shows (docs/gbuffer.md, header): the time the
// scene was posed at, the frame rate that put frames there and the animations that played, so
// that a later stage (dhdr-light --scene) poses the scene where the pixels are.
#pragma once

#include <OpenImageIO/oiioversion.h>
#include <optional>
#include <string>
#include <vector>

OIIO_NAMESPACE_BEGIN
class ImageSpec;
OIIO_NAMESPACE_END

namespace dhdr::gbuffer {

// Header attributes of a G-buffer rendered with animation. The time and the frame rate are
// doubles, the very numbers the scene was posed with (a float time would pose it a few ulps
// elsewhere); files from before they were doubles hold floats, which are read too.
inline constexpr const char* kAnimationTime = "dhdr:animationTime"; // seconds
inline constexpr const char* kFps = "dhdr:fps";
// The animations that played: their indices in the scene file, comma-separated ("0", "0,1").
inline constexpr const char* kAnimation = "dhdr:animation";

struct Moment {
    double time = 0.0; // seconds
    double fps = 0.0;  // 0: not recorded
    // Indices into the scene file's animations; unrecorded (a file from before they were
    // recorded): the file's first animation, dhdr-gbuffer's default.
    std::optional<std::vector<int>> animations;
};

void writeMoment(OIIO::ImageSpec& spec, const Moment& moment);

// The moment `spec` records; none (nullopt) for a G-buffer without animation. False with
// `error` when the attributes are there but malformed (a time that is not a finite number, an
// animation list that is not indices).
bool readMoment(const OIIO::ImageSpec& spec, std::optional<Moment>& moment, std::string& error);

// "0,2" for {0, 2}.
std::string formatAnimations(const std::vector<int>& animations);

} // namespace dhdr::gbuffer
