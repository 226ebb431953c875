// The baked IBL as one multi-part EXR (writeIbl, loadIbl).
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <cmath>
#include <dhdr/deferred/environment/ibl.h>
#include <dhdr/io/exr_header.h>

namespace dhdr {

namespace {

constexpr const char* kShAttribute = "dhdr:irradianceSH";

void setParams(OIIO::ImageSpec& spec, const Ibl& ibl) {
    // OpenEXR's parts share one display window: level 0's.
    spec.full_x = spec.full_y = 0;
    spec.full_width = ibl.levels.empty() ? spec.width : ibl.levels[0].width;
    spec.full_height = ibl.levels.empty() ? spec.height : ibl.levels[0].height;
    std::vector<float> sh;
    for (const glm::vec3& c : ibl.sh)
        sh.insert(sh.end(), {c.r, c.g, c.b});
    spec.attribute(kShAttribute, OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 27), sh.data());
    spec.attribute("dhdr:iblLevels", ibl.params.levels);
    spec.attribute("dhdr:iblBaseWidth", ibl.params.baseWidth);
    spec.attribute("dhdr:iblSamples", ibl.params.samples);
    spec.attribute("dhdr:dfgSize", ibl.params.dfgSize);
    spec.attribute("dhdr:dfgSamples", ibl.params.dfgSamples);
    spec.attribute("dhdr:sunThreshold", ibl.params.sunThreshold);
    if (ibl.sun.found()) {
        const glm::vec3 d = ibl.sun.direction, e = ibl.sun.illuminance;
        const float direction[3] = {d.x, d.y, d.z}, illuminance[3] = {e.r, e.g, e.b};
        spec.attribute("dhdr:sunDirection", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 3), direction);
        spec.attribute("dhdr:sunIlluminance", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 3),
                       illuminance);
        spec.attribute("dhdr:sunAngle", ibl.sun.angle);
        spec.attribute("dhdr:sunShare", float(ibl.sun.share));
    }
}

// The sun a bake split off, from its header; false with `error` when what is there is not a
// sun (not finite, not a unit direction, a negative illuminance, an angle outside [0, π)).
bool readSun(const OIIO::ImageSpec& spec, EnvironmentSun& sun, std::string& error) {
    sun = EnvironmentSun();
    sun.threshold = spec.get_float_attribute("dhdr:sunThreshold", 0.0f);
    const OIIO::ParamValue* d = spec.find_attribute("dhdr:sunDirection");
    const OIIO::ParamValue* e = spec.find_attribute("dhdr:sunIlluminance");
    if (!d && !e) return true;
    // Written as float[3]; OpenEXR gives them back as V3f.
    auto three = [](const OIIO::ParamValue* p) {
        return p && p->type().basetype == OIIO::TypeDesc::FLOAT && p->type().basevalues() == 3 &&
               p->nvalues() == 1;
    };
    if (!three(d) || !three(e)) {
        error = "a baked IBL file with half of a sun";
        return false;
    }
    const float* dv = static_cast<const float*>(d->data());
    const float* ev = static_cast<const float*>(e->data());
    sun.direction = {dv[0], dv[1], dv[2]};
    sun.illuminance = {ev[0], ev[1], ev[2]};
    sun.angle = spec.get_float_attribute("dhdr:sunAngle", -1.0f);
    sun.share = spec.get_float_attribute("dhdr:sunShare", 0.0f);
    const float length = glm::length(sun.direction);
    const bool ok = std::isfinite(length) && std::abs(length - 1.0f) < 1e-3f && sun.angle >= 0.0f &&
                    sun.angle < 3.14159265f && ev[0] >= 0.0f && ev[1] >= 0.0f && ev[2] >= 0.0f &&
                    std::isfinite(ev[0] + ev[1] + ev[2]);
    if (!ok) {
        error = "a baked IBL file whose sun is not one (direction, angle or illuminance)";
        return false;
    }
    return true;
}

} // namespace

bool writeIbl(const std::string& path, const Ibl& ibl, std::string& error) {
    std::vector<OIIO::ImageSpec> specs;
    for (size_t k = 0; k < ibl.levels.size(); ++k) {
        OIIO::ImageSpec spec(ibl.levels[k].width, ibl.levels[k].height, 3, OIIO::TypeDesc::FLOAT);
        spec.channelnames = {"R", "G", "B"};
        spec.attribute("oiio:subimagename", "specular" + std::to_string(k));
        spec.attribute("dhdr:roughness", iblLevelRoughness(int(k), int(ibl.levels.size())));
        spec.attribute("compression", "zip");
        setParams(spec, ibl);
        specs.push_back(spec);
    }
    OIIO::ImageSpec dfg(ibl.params.dfgSize, ibl.params.dfgSize, 2, OIIO::TypeDesc::FLOAT);
    dfg.channelnames = {"dfg.x", "dfg.y"};
    dfg.attribute("oiio:subimagename", "dfg");
    setParams(dfg, ibl);
    specs.push_back(dfg);
    auto out = OIIO::ImageOutput::create(path);
    if (!out || !out->supports("multiimage")) {
        error = "cannot write a multi-part EXR here";
        return false;
    }
    if (!out->open(path, int(specs.size()), specs.data())) {
        error = out->geterror();
        return false;
    }
    for (size_t k = 0; k < specs.size(); ++k) {
        if (k > 0 && !out->open(path, specs[k], OIIO::ImageOutput::AppendSubimage)) {
            error = out->geterror();
            return false;
        }
        const void* data = k < ibl.levels.size()
                               ? static_cast<const void*>(ibl.levels[k].rgb.data())
                               : static_cast<const void*>(ibl.dfg.data());
        if (!out->write_image(OIIO::TypeDesc::FLOAT, data)) {
            error = out->geterror();
            return false;
        }
    }
    if (!out->close()) {
        error = out->geterror();
        return false;
    }
    return true;
}

bool loadIbl(const std::string& path, const IblBakeParams& params, Ibl& ibl, bool& baked,
             std::string& error, long long* replaced, int nthreads) {
    if (!detail::exrHeadersFit(path, error)) return false;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        error = "cannot read: " + OIIO::geterror();
        return false;
    }
    const OIIO::ImageSpec first = in->spec();
    const OIIO::ParamValue* sh = first.find_attribute(kShAttribute);
    baked = false;
    if (!sh || sh->type() != OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 27)) {
        in->close();
        EnvironmentImage env;
        if (!readEnvironmentImage(path, env, error, replaced)) return false;
        baked = true;
        return bakeIbl(env, params, ibl, error, nthreads);
    }
    // A baked file is dhdr's own output, which never holds NaN or Inf: one that does was
    // damaged or written by something else, and would light the frame black, so every number
    // read from it is checked.
    const float* c = static_cast<const float*>(sh->data());
    for (int i = 0; i < 27; ++i)
        if (!std::isfinite(c[i])) {
            error = "a baked IBL file whose spherical harmonics are not finite";
            return false;
        }
    for (int i = 0; i < 9; ++i)
        ibl.sh[size_t(i)] = glm::vec3(c[3 * i], c[3 * i + 1], c[3 * i + 2]);
    ibl.params.levels = first.get_int_attribute("dhdr:iblLevels");
    ibl.params.baseWidth = first.get_int_attribute("dhdr:iblBaseWidth");
    ibl.params.samples = first.get_int_attribute("dhdr:iblSamples");
    ibl.params.dfgSize = first.get_int_attribute("dhdr:dfgSize");
    ibl.params.dfgSamples = first.get_int_attribute("dhdr:dfgSamples");
    ibl.params.sunThreshold = first.get_float_attribute("dhdr:sunThreshold", 0.0f);
    if (!readSun(first, ibl.sun, error)) return false;
    in->close();
    if (ibl.params.levels < 2 || ibl.params.dfgSize < 2) {
        error = "a baked IBL file without its levels";
        return false;
    }
    ibl.levels.clear();
    for (int k = 0; k < ibl.params.levels; ++k) {
        EnvironmentImage level;
        long long n = 0;
        if (!readEnvironmentImage(path, level, error, &n, k)) return false;
        if (n > 0) {
            error = "level " + std::to_string(k) + " of a baked IBL file has " + std::to_string(n) +
                    " texels that are not finite";
            return false;
        }
        ibl.levels.push_back(std::move(level));
    }
    OIIO::ImageBuf dfg(path, ibl.params.levels, 0);
    if (!dfg.read(ibl.params.levels, 0, true, OIIO::TypeDesc::FLOAT) ||
        dfg.spec().width != ibl.params.dfgSize || dfg.spec().height != ibl.params.dfgSize ||
        dfg.nchannels() != 2) {
        error = "a baked IBL file without its DFG table";
        return false;
    }
    const float* p = static_cast<const float*>(dfg.localpixels());
    ibl.dfg.assign(p == nullptr ? 0 : size_t(ibl.params.dfgSize) * size_t(ibl.params.dfgSize),
                   glm::vec2(0.0f));
    for (size_t i = 0; i < ibl.dfg.size(); ++i) {
        ibl.dfg[i] = {p[2 * i], p[2 * i + 1]};
        if (!std::isfinite(ibl.dfg[i].x) || !std::isfinite(ibl.dfg[i].y)) {
            error = "a baked IBL file whose DFG table is not finite";
            return false;
        }
    }
    ibl.sampler.build(ibl.levels[0]);
    if (replaced) *replaced = 0;
    return true;
}

} // namespace dhdr
