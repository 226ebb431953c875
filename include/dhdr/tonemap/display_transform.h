// Colour management through OpenColorIO: the input's colour space to scene-linear, and
// scene-linear to a display and view. Without a config, a built-in one (below) is used.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <memory>
#include <string>

namespace dhdr {

struct DisplaySettings {
    std::string config;     // a config file; empty: $OCIO, else the built-in config
    std::string colorspace; // the input's colour space; empty: the scene_linear role
    std::string display;    // empty: the config's default display
    std::string view;       // empty: the display's default view
    std::string look;       // empty: none
};

// The built-in config, made from OpenColorIO's built-in transforms: scene-linear Rec.709
// ("Linear Rec.709 (sRGB)", the scene_linear role), ACEScg and ACES2065-1 (the reference);
// display "sRGB" with views "Standard" (colour encoded as it is) and "ACES" (the ACES 1.0 SDR
// video output transform).
inline constexpr const char* kBuiltinSceneLinear = "Linear Rec.709 (sRGB)";
// Also in the built-in config: sRGB-encoded Rec.709 (alias "sRGB"), what PNG and JPEG hold.
inline constexpr const char* kBuiltinSrgbTexture = "sRGB - Texture";

class DisplayTransform {
public:
    DisplayTransform();
    ~DisplayTransform();

    // Loads the config and checks every name; an unknown one gets an error listing the valid
    // ones.
    bool init(const DisplaySettings& settings, std::string& error);
    // "sRGB / Standard (built-in config)" and the like.
    std::string describe() const;
    // The colour space of the display's encoded values, as file metadata names it: "sRGB"
    // when the config's name for it says sRGB (PNG then gets its sRGB chunk), else that name.
    std::string outputColorSpace() const;

    // In place on the colour channels (the first three) over `roi` (default: all of `img`):
    // input colour space → scene-linear (a no-op when they are the same), and scene-linear →
    // display (look, view, display). `img` must hold float pixels in memory. Without an
    // explicit input colour space, an image whose `oiio:ColorSpace` says sRGB (PNG, JPEG:
    // display-encoded values) is decoded from the config's "sRGB" colour space, when it has
    // one, rather than taken as scene-linear.
    bool toSceneLinear(OIIO::ImageBuf& img, OIIO::ROI roi = {}, int nthreads = 0) const;
    bool toDisplay(OIIO::ImageBuf& img, OIIO::ROI roi = {}, int nthreads = 0) const;
    // The colour space toSceneLinear takes an image of `spec` from, when it is not the
    // configured input's (a file tagged sRGB); empty otherwise.
    std::string inputColorSpace(const OIIO::ImageSpec& spec) const;
    // Whether a file's metadata says it holds sRGB-encoded values.
    static bool saysSrgb(const OIIO::ImageSpec& spec);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace dhdr
