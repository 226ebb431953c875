#include <OpenImageIO/imageio.h>
#include <cmath>
#include <dhdr/deferred/gbuffer/gbuffer_time.h>

namespace dhdr::gbuffer {

std::string formatAnimations(const std::vector<int>& animations) {
    std::string out;
    for (size_t i = 0; i < animations.size(); ++i)
        out += (i ? "," : "") + std::to_string(animations[i]);
    return out;
}

void writeMoment(OIIO::ImageSpec& spec, const Moment& moment) {
    spec.attribute(kAnimationTime, OIIO::TypeDesc::DOUBLE, &moment.time);
    if (moment.fps > 0.0) spec.attribute(kFps, OIIO::TypeDesc::DOUBLE, &moment.fps);
    if (moment.animations) spec.attribute(kAnimation, formatAnimations(*moment.animations));
}

namespace {

// A numeric attribute as a double (float or double in the file); nullopt when absent.
bool numberOf(const OIIO::ImageSpec& spec, const char* name, std::optional<double>& value,
              std::string& error) {
    value.reset();
    const OIIO::ParamValue* p = spec.find_attribute(name);
    if (!p) return true;
    const OIIO::TypeDesc t = p->type();
    if (t == OIIO::TypeDesc::DOUBLE)
        value = *static_cast<const double*>(p->data());
    else if (t == OIIO::TypeDesc::FLOAT)
        value = double(*static_cast<const float*>(p->data()));
    if (!value || !std::isfinite(*value)) {
        error = std::string(name) + " is not a finite number";
        return false;
    }
    return true;
}

} // namespace

bool readMoment(const OIIO::ImageSpec& spec, std::optional<Moment>& moment, std::string& error) {
    moment.reset();
    std::optional<double> time, fps;
    if (!numberOf(spec, kAnimationTime, time, error) || !numberOf(spec, kFps, fps, error))
        return false;
    if (!time) return true;
    Moment m;
    m.time = *time;
    m.fps = fps.value_or(0.0);
    if (const OIIO::ParamValue* p = spec.find_attribute(kAnimation)) {
        const std::string list = p->type() == OIIO::TypeString ? p->get_string() : "";
        std::vector<int> indices;
        size_t at = 0;
        bool ok = !list.empty();
        while (ok && at <= list.size()) {
            const size_t comma = std::min(list.find(',', at), list.size());
            const std::string item = list.substr(at, comma - at);
            ok = !item.empty() && item.size() < 9 &&
                 item.find_first_not_of("0123456789") == std::string::npos;
            if (ok) indices.push_back(std::stoi(item));
            at = comma + 1;
        }
        if (!ok) {
            error = std::string(kAnimation) + " '" + list +
                    "' is not a list of animation indices (\"0\", \"0,1\")";
            return false;
        }
        m.animations = indices;
    }
    moment = m;
    return true;
}

} // namespace dhdr::gbuffer
