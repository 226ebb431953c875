#include <OpenColorIO/OpenColorIO.h>
#include <OpenImageIO/parallel.h>
#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <dhdr/common/parallel.h>
#include <dhdr/tonemap/display_transform.h>
#include <vector>

namespace OCIO = OCIO_NAMESPACE;

namespace dhdr {

namespace {

OCIO::ConstConfigRcPtr builtinConfig() {
    OCIO::ConfigRcPtr config = OCIO::Config::Create();
    config->setName("dhdr built-in");
    auto builtin = [](const char* style, bool inverse = false) {
        OCIO::BuiltinTransformRcPtr t = OCIO::BuiltinTransform::Create();
        t->setStyle(style);
        if (inverse) t->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
        return t;
    };
    // Scene reference: ACES2065-1.
    OCIO::ColorSpaceRcPtr aces = OCIO::ColorSpace::Create(OCIO::REFERENCE_SPACE_SCENE);
    aces->setName("ACES2065-1");
    config->addColorSpace(aces);
    OCIO::ColorSpaceRcPtr acescg = OCIO::ColorSpace::Create(OCIO::REFERENCE_SPACE_SCENE);
    acescg->setName("ACEScg");
    acescg->setTransform(builtin("ACEScg_to_ACES2065-1"), OCIO::COLORSPACE_DIR_TO_REFERENCE);
    config->addColorSpace(acescg);
    OCIO::ColorSpaceRcPtr rec709 = OCIO::ColorSpace::Create(OCIO::REFERENCE_SPACE_SCENE);
    rec709->setName(kBuiltinSceneLinear);
    OCIO::GroupTransformRcPtr toAces = OCIO::GroupTransform::Create();
    toAces->appendTransform(builtin("UTILITY - ACES-AP1_to_LINEAR-REC709_BFD", true));
    toAces->appendTransform(builtin("ACEScg_to_ACES2065-1"));
    rec709->setTransform(toAces, OCIO::COLORSPACE_DIR_TO_REFERENCE);
    config->addColorSpace(rec709);
    // sRGB-encoded Rec.709, as PNG and JPEG files hold it: the piecewise sRGB curve
    // (IEC 61966-2-1: exponent 2.4, offset 0.055), then as linear Rec.709.
    OCIO::ColorSpaceRcPtr srgbTexture = OCIO::ColorSpace::Create(OCIO::REFERENCE_SPACE_SCENE);
    srgbTexture->setName(kBuiltinSrgbTexture);
    srgbTexture->addAlias("sRGB");
    OCIO::ExponentWithLinearTransformRcPtr curve = OCIO::ExponentWithLinearTransform::Create();
    const double gamma[4] = {2.4, 2.4, 2.4, 1.0}, offset[4] = {0.055, 0.055, 0.055, 0.0};
    curve->setGamma(gamma);
    curve->setOffset(offset);
    OCIO::GroupTransformRcPtr decode = OCIO::GroupTransform::Create();
    decode->appendTransform(curve);
    decode->appendTransform(toAces);
    srgbTexture->setTransform(decode, OCIO::COLORSPACE_DIR_TO_REFERENCE);
    config->addColorSpace(srgbTexture);
    config->setRole(OCIO::ROLE_SCENE_LINEAR, kBuiltinSceneLinear);
    config->setRole(OCIO::ROLE_DEFAULT, kBuiltinSceneLinear);

    // Display reference: CIE XYZ D65.
    OCIO::ColorSpaceRcPtr srgb = OCIO::ColorSpace::Create(OCIO::REFERENCE_SPACE_DISPLAY);
    srgb->setName("sRGB - Display");
    srgb->setTransform(builtin("DISPLAY - CIE-XYZ-D65_to_sRGB"),
                       OCIO::COLORSPACE_DIR_FROM_REFERENCE);
    config->addColorSpace(srgb);
    OCIO::ViewTransformRcPtr standard = OCIO::ViewTransform::Create(OCIO::REFERENCE_SPACE_SCENE);
    standard->setName("Un-tone-mapped");
    standard->setTransform(builtin("UTILITY - ACES-AP0_to_CIE-XYZ-D65_BFD"),
                           OCIO::VIEWTRANSFORM_DIR_FROM_REFERENCE);
    config->addViewTransform(standard);
    OCIO::ViewTransformRcPtr acesView = OCIO::ViewTransform::Create(OCIO::REFERENCE_SPACE_SCENE);
    acesView->setName("ACES 1.0 - SDR Video");
    acesView->setTransform(builtin("ACES-OUTPUT - ACES2065-1_to_CIE-XYZ-D65 - SDR-VIDEO_1.0"),
                           OCIO::VIEWTRANSFORM_DIR_FROM_REFERENCE);
    config->addViewTransform(acesView);
    config->addDisplayView("sRGB", "Standard", "Un-tone-mapped", "sRGB - Display", "", "", "");
    config->addDisplayView("sRGB", "ACES", "ACES 1.0 - SDR Video", "sRGB - Display", "", "", "");
    config->setActiveDisplays("sRGB");
    config->setActiveViews("Standard, ACES");
    config->validate();
    return config;
}

std::string listOf(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names)
        out += (out.empty() ? "" : ", ") + n;
    return out;
}

void applyRgb(const OCIO::ConstCPUProcessorRcPtr& cpu, OIIO::ImageBuf& img, OIIO::ROI roi,
              int nthreads) {
    roi = OIIO::roi_intersection(roi.defined() ? roi : img.roi(), img.roi());
    const int nch = img.nchannels();
    OIIO::parallel_for(
        int64_t(roi.ybegin), int64_t(roi.yend),
        [&](int64_t y) {
            float* row = static_cast<float*>(img.pixeladdr(roi.xbegin, int(y)));
            OCIO::PackedImageDesc desc(row, roi.width(), 1, 3, OCIO::BIT_DEPTH_F32, sizeof(float),
                                       ptrdiff_t(nch * sizeof(float)),
                                       ptrdiff_t(roi.width() * nch * sizeof(float)));
            cpu->apply(desc);
        },
        perItem(nthreads));
}

} // namespace

struct DisplayTransform::Impl {
    OCIO::ConstConfigRcPtr config;
    std::string source; // where the config came from
    OCIO::ConstCPUProcessorRcPtr toScene, toDisplay;
    // From the config's "sRGB" colour space, for files that say they hold sRGB-encoded
    // values; null when the config has none or --colorspace was given.
    OCIO::ConstCPUProcessorRcPtr fromSrgb;
    std::string srgbName;
    std::string display, view;
};

DisplayTransform::DisplayTransform() : m_impl(std::make_unique<Impl>()) {}
DisplayTransform::~DisplayTransform() = default;

bool DisplayTransform::init(const DisplaySettings& s, std::string& error) {
    Impl& m = *m_impl;
    try {
        const char* env = std::getenv("OCIO");
        if (!s.config.empty()) {
            m.config = OCIO::Config::CreateFromFile(s.config.c_str());
            m.source = s.config;
        } else if (env && *env) {
            m.config = OCIO::Config::CreateFromEnv();
            m.source = std::string("$OCIO ") + env;
        } else {
            m.config = builtinConfig();
            m.source = "built-in config";
        }
    } catch (const OCIO::Exception& e) {
        error = (s.config.empty() ? std::string("$OCIO") : s.config) + ": " + e.what();
        return false;
    }
    const OCIO::ConstConfigRcPtr& config = m.config;
    const OCIO::ConstColorSpaceRcPtr sceneLinear = config->getColorSpace(OCIO::ROLE_SCENE_LINEAR);
    if (!sceneLinear) {
        error = m.source + ": the config has no scene_linear role";
        return false;
    }
    const std::string input = s.colorspace.empty() ? sceneLinear->getName() : s.colorspace;
    if (!config->getColorSpace(input.c_str())) {
        std::vector<std::string> names;
        for (int i = 0; i < config->getNumColorSpaces(); ++i)
            names.push_back(config->getColorSpaceNameByIndex(i));
        error =
            "unknown colour space '" + input + "' (" + m.source + " has: " + listOf(names) + ")";
        return false;
    }
    m.display = s.display.empty() ? config->getDefaultDisplay() : s.display;
    std::vector<std::string> displays;
    bool displayFound = false;
    for (int i = 0; i < config->getNumDisplays(); ++i) {
        displays.push_back(config->getDisplay(i));
        displayFound = displayFound || displays.back() == m.display;
    }
    if (!displayFound) {
        error =
            "unknown display '" + m.display + "' (" + m.source + " has: " + listOf(displays) + ")";
        return false;
    }
    m.view = s.view.empty() ? config->getDefaultView(m.display.c_str()) : s.view;
    std::vector<std::string> views;
    bool viewFound = false;
    for (int i = 0; i < config->getNumViews(m.display.c_str()); ++i) {
        views.push_back(config->getView(m.display.c_str(), i));
        viewFound = viewFound || views.back() == m.view;
    }
    if (!viewFound) {
        error = "unknown view '" + m.view + "' of display '" + m.display +
                "' (it has: " + listOf(views) + ")";
        return false;
    }
    if (!s.look.empty() && !config->getLook(s.look.c_str())) {
        std::vector<std::string> looks;
        for (int i = 0; i < config->getNumLooks(); ++i)
            looks.push_back(config->getLookNameByIndex(i));
        error = "unknown look '" + s.look + "' (" + m.source +
                " has: " + (looks.empty() ? std::string("none") : listOf(looks)) + ")";
        return false;
    }
    try {
        m.toScene =
            config->getProcessor(input.c_str(), sceneLinear->getName())->getDefaultCPUProcessor();
        if (s.colorspace.empty()) {
            if (const auto srgb = config->getColorSpace("sRGB")) {
                m.srgbName = srgb->getName();
                m.fromSrgb = config->getProcessor(srgb->getName(), sceneLinear->getName())
                                 ->getDefaultCPUProcessor();
            }
        }
        OCIO::GroupTransformRcPtr display = OCIO::GroupTransform::Create();
        if (!s.look.empty()) {
            OCIO::LookTransformRcPtr look = OCIO::LookTransform::Create();
            look->setSrc(sceneLinear->getName());
            look->setDst(sceneLinear->getName());
            look->setLooks(s.look.c_str());
            display->appendTransform(look);
        }
        OCIO::DisplayViewTransformRcPtr dv = OCIO::DisplayViewTransform::Create();
        dv->setSrc(sceneLinear->getName());
        dv->setDisplay(m.display.c_str());
        dv->setView(m.view.c_str());
        display->appendTransform(dv);
        m.toDisplay = config->getProcessor(display)->getDefaultCPUProcessor();
    } catch (const OCIO::Exception& e) {
        error = m.source + ": " + e.what();
        return false;
    }
    return true;
}

std::string DisplayTransform::describe() const {
    return m_impl->display + " / " + m_impl->view + " (" + m_impl->source + ")";
}

std::string DisplayTransform::outputColorSpace() const {
    const Impl& m = *m_impl;
    if (!m.config) return {};
    const char* name = m.config->getDisplayViewColorSpaceName(m.display.c_str(), m.view.c_str());
    std::string colorspace = name ? name : "";
    std::string lower = colorspace;
    std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
    return lower.find("srgb") != std::string::npos ? "sRGB" : colorspace;
}

bool DisplayTransform::toSceneLinear(OIIO::ImageBuf& img, OIIO::ROI roi, int nthreads) const {
    if (!m_impl->toScene || img.spec().format != OIIO::TypeDesc::FLOAT || !img.localpixels())
        return false;
    const OCIO::ConstCPUProcessorRcPtr& cpu =
        saysSrgb(img.spec()) && m_impl->fromSrgb ? m_impl->fromSrgb : m_impl->toScene;
    if (!cpu->isNoOp()) applyRgb(cpu, img, roi, nthreads);
    return true;
}

std::string DisplayTransform::inputColorSpace(const OIIO::ImageSpec& spec) const {
    if (saysSrgb(spec) && m_impl->fromSrgb) return m_impl->srgbName;
    return {};
}

bool DisplayTransform::saysSrgb(const OIIO::ImageSpec& spec) {
    std::string tag = spec.get_string_attribute("oiio:ColorSpace");
    std::transform(tag.begin(), tag.end(), tag.begin(), ::tolower);
    return tag.find("srgb") != std::string::npos && tag.find("linear") == std::string::npos;
}

bool DisplayTransform::toDisplay(OIIO::ImageBuf& img, OIIO::ROI roi, int nthreads) const {
    if (!m_impl->toDisplay || img.spec().format != OIIO::TypeDesc::FLOAT || !img.localpixels())
        return false;
    applyRgb(m_impl->toDisplay, img, roi, nthreads);
    return true;
}

} // namespace dhdr
