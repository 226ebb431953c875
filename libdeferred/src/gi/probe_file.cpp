// A probe volume as one two-part EXR (writeProbes, readProbes).
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <cmath>
#include <dhdr/deferred/gi/probes.h>
#include <dhdr/io/exr_header.h>
#include <initializer_list>

namespace dhdr {

namespace {

// Probes per atlas row: a near-square atlas.
int atlasColumns(int probes) {
    return std::max(1, int(std::ceil(std::sqrt(double(probes)))));
}

void setGrid(OIIO::ImageSpec& spec, const ProbeVolume& v) {
    const float origin[3] = {float(v.origin.x), float(v.origin.y), float(v.origin.z)};
    const float spacing[3] = {float(v.spacing.x), float(v.spacing.y), float(v.spacing.z)};
    const int counts[3] = {v.counts.x, v.counts.y, v.counts.z};
    spec.attribute("dhdr:probeOrigin", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 3), origin);
    spec.attribute("dhdr:probeSpacing", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 3), spacing);
    spec.attribute("dhdr:probeCounts", OIIO::TypeDesc(OIIO::TypeDesc::INT, 3), counts);
    spec.attribute("dhdr:probeRays", v.rays);
    spec.attribute("dhdr:probeBounces", v.bounces);
    spec.attribute("dhdr:probeDiffuse", v.diffuse == DiffuseModel::Burley ? "burley" : "lambert");
    // As floats: OpenImageIO's EXR writer drops int arrays other than vectors.
    std::vector<float> states;
    std::vector<float> positions;
    for (size_t p = 0; p < v.states.size(); ++p) {
        states.push_back(float(int(v.states[p])));
        positions.insert(positions.end(), {v.positions[p].x, v.positions[p].y, v.positions[p].z});
    }
    spec.attribute("dhdr:probeStates", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, int(states.size())),
                   states.data());
    spec.attribute("dhdr:probePositions",
                   OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, int(positions.size())), positions.data());
    spec.attribute("dhdr:probeNormalBias", v.normalBias);
    spec.attribute("dhdr:probeViewBias", v.viewBias);
    // The same attributes as a G-buffer's (dhdr:animationTime ...): one reader for both.
    if (v.moment) gbuffer::writeMoment(spec, *v.moment);
}

// The probe attributes of the irradiance part's header (null where missing).
struct ProbeAttributes {
    const OIIO::ParamValue *counts, *origin, *spacing, *states, *positions;
};

// Values of an attribute whatever its aggregate (OpenEXR reads a 3-array back as a vector).
int values(const OIIO::ParamValue* v) {
    return int(v->type().basevalues());
}

bool findProbeAttributes(const OIIO::ImageSpec& irr, ProbeAttributes& at, std::string& error) {
    at.counts = irr.find_attribute("dhdr:probeCounts");
    at.origin = irr.find_attribute("dhdr:probeOrigin");
    at.spacing = irr.find_attribute("dhdr:probeSpacing");
    at.states = irr.find_attribute("dhdr:probeStates");
    at.positions = irr.find_attribute("dhdr:probePositions");
    if (!at.counts || !at.origin || !at.spacing || !at.states || !at.positions ||
        values(at.counts) != 3 || values(at.origin) != 3 || values(at.spacing) != 3 ||
        at.counts->type().basetype != OIIO::TypeDesc::INT ||
        at.origin->type().basetype != OIIO::TypeDesc::FLOAT ||
        at.spacing->type().basetype != OIIO::TypeDesc::FLOAT) {
        error = "not a probe volume (no dhdr:probeCounts, dhdr:probeOrigin, dhdr:probeSpacing, "
                "dhdr:probeStates, dhdr:probePositions; dhdr-probes writes them)";
        return false;
    }
    return true;
}

// A fresh `v` with the grid's counts, origin and spacing.
bool readGrid(const ProbeAttributes& at, ProbeVolume& v, std::string& error) {
    v = ProbeVolume{};
    const int* c = static_cast<const int*>(at.counts->data());
    const float* o = static_cast<const float*>(at.origin->data());
    const float* s = static_cast<const float*>(at.spacing->data());
    for (int a = 0; a < 3; ++a) {
        v.counts[a] = c[a];
        v.origin[a] = o[a];
        v.spacing[a] = s[a];
        if (c[a] < 1 || c[a] > kMaxProbesPerAxis || !(s[a] > 0.0f) || !std::isfinite(s[a]) ||
            !std::isfinite(o[a])) {
            error = "probe grid out of range";
            return false;
        }
    }
    return true;
}

// Do the per-probe attributes and the irradiance atlas hold `v`'s grid?
bool irradianceFitsGrid(const ProbeAttributes& at, const OIIO::ImageSpec& irr, const ProbeVolume& v,
                        std::string& error) {
    const int n = v.probeCount();
    const int cols = atlasColumns(n), rows = (n + cols - 1) / cols;
    const int wi = ProbeVolume::kIrradianceTexels + 2;
    if (values(at.states) != n || values(at.positions) != 3 * n || irr.width != cols * wi ||
        irr.height != rows * wi || irr.nchannels < 3) {
        error = "the probe atlas does not match its grid (" + std::to_string(wi - 2) + " x " +
                std::to_string(wi - 2) + " irradiance texels a probe; a file from an earlier " +
                "dhdr-probes, with 6 x 6 or 8 x 8, must be baked again)";
        return false;
    }
    return true;
}

// How the volume was baked: rays, bounces, diffuse model, moment, and the shading biases.
bool readBakeRecord(const OIIO::ImageSpec& irr, ProbeVolume& v, std::string& error) {
    v.rays = irr.get_int_attribute("dhdr:probeRays");
    v.bounces = irr.get_int_attribute("dhdr:probeBounces");
    // Files from before the attribute were baked with Lambert's.
    const std::string diffuse = irr.get_string_attribute("dhdr:probeDiffuse", "lambert");
    if (diffuse != "lambert" && diffuse != "burley") {
        error = "unknown diffuse model '" + diffuse + "' (dhdr:probeDiffuse)";
        return false;
    }
    v.diffuse = diffuse == "burley" ? DiffuseModel::Burley : DiffuseModel::Lambert;
    if (!gbuffer::readMoment(irr, v.moment, error)) return false;
    v.normalBias = irr.get_float_attribute("dhdr:probeNormalBias", v.normalBias);
    v.viewBias = irr.get_float_attribute("dhdr:probeViewBias", v.viewBias);
    // A NaN bias moves every shading point to NaN: indirect light 0 everywhere, silently.
    for (const auto& [name, bias] : {std::pair{"dhdr:probeNormalBias", v.normalBias},
                                     std::pair{"dhdr:probeViewBias", v.viewBias}})
        if (!(bias >= 0.0f && bias <= 1.0f)) {
            error = std::string(name) + " " + std::to_string(bias) +
                    " is not a bias in [0, 1] spacings";
            return false;
        }
    return true;
}

// Each probe's state and (finite) position.
bool readProbeStates(const ProbeAttributes& at, ProbeVolume& v, std::string& error) {
    const int n = v.probeCount();
    if (at.states->type().basetype != OIIO::TypeDesc::FLOAT ||
        at.positions->type().basetype != OIIO::TypeDesc::FLOAT) {
        error = "probe states or positions of the wrong type";
        return false;
    }
    const float* st = static_cast<const float*>(at.states->data());
    const float* pos = static_cast<const float*>(at.positions->data());
    for (int p = 0; p < 3 * n; ++p)
        if (!std::isfinite(pos[p])) {
            error = "probe " + std::to_string(p / 3) + "'s position is not finite";
            return false;
        }
    for (int p = 0; p < n; ++p) {
        v.states.push_back(st[p] == 2.0f   ? ProbeState::Off
                           : st[p] == 1.0f ? ProbeState::Relocated
                                           : ProbeState::Active);
        v.positions.emplace_back(pos[3 * p], pos[3 * p + 1], pos[3 * p + 2]);
    }
    return true;
}

// The two atlases' pixels as they lie in the file (irradiance RGB, then distance moments).
struct AtlasPixels {
    std::vector<float> irradiance, distance;
    int irradianceWidth = 0, distanceWidth = 0;
};

bool readAtlasPixels(OIIO::ImageInput& in, const OIIO::ImageSpec& irr, const ProbeVolume& v,
                     AtlasPixels& px, std::string& error) {
    const int n = v.probeCount();
    const int cols = atlasColumns(n), rows = (n + cols - 1) / cols;
    const int wd = ProbeVolume::kDistanceTexels + 2;
    px.irradianceWidth = irr.width;
    px.irradiance.resize(size_t(irr.width) * size_t(irr.height) * 3);
    if (!in.read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.irradiance.data()) ||
        !in.seek_subimage(1, 0)) {
        error = "cannot read the irradiance atlas or find the distance part: " + in.geterror();
        return false;
    }
    const OIIO::ImageSpec dist = in.spec();
    if (dist.width != cols * wd || dist.height != rows * wd || dist.nchannels < 2) {
        error = "the distance atlas does not match its grid";
        return false;
    }
    px.distanceWidth = dist.width;
    px.distance.resize(size_t(dist.width) * size_t(dist.height) * 2);
    if (!in.read_image(1, 0, 0, 2, OIIO::TypeDesc::FLOAT, px.distance.data())) {
        error = "cannot read the distance atlas: " + in.geterror();
        return false;
    }
    return true;
}

// Each probe's bordered maps cut out of the atlases; all their texels finite.
bool unpackAtlases(const AtlasPixels& px, ProbeVolume& v, std::string& error) {
    const int n = v.probeCount(), cols = atlasColumns(n);
    const int wi = ProbeVolume::kIrradianceTexels + 2, wd = ProbeVolume::kDistanceTexels + 2;
    const std::vector<float>&a = px.irradiance, &b = px.distance;
    v.irradiance.resize(size_t(n) * size_t(wi * wi));
    v.distance.resize(size_t(n) * size_t(wd * wd));
    long long bad = 0;
    for (int p = 0; p < n; ++p) {
        const int cx = p % cols, cy = p / cols;
        for (int y = 0; y < wi; ++y)
            for (int x = 0; x < wi; ++x) {
                const float* q = &a[3 * (size_t(cy * wi + y) * size_t(px.irradianceWidth) +
                                         size_t(cx * wi + x))];
                glm::vec3& e = v.irradiance[size_t(p) * size_t(wi * wi) + size_t(y * wi + x)];
                e = glm::vec3(q[0], q[1], q[2]);
                bad += !std::isfinite(e.r + e.g + e.b);
            }
        for (int y = 0; y < wd; ++y)
            for (int x = 0; x < wd; ++x) {
                const float* q =
                    &b[2 * (size_t(cy * wd + y) * size_t(px.distanceWidth) + size_t(cx * wd + x))];
                glm::vec2& d = v.distance[size_t(p) * size_t(wd * wd) + size_t(y * wd + x)];
                d = glm::vec2(q[0], q[1]);
                bad += !std::isfinite(d.x + d.y);
            }
    }
    if (bad > 0) {
        error = std::to_string(bad) + " probe texels are not finite";
        return false;
    }
    return true;
}

} // namespace

bool writeProbes(const std::string& path, const ProbeVolume& v, std::string& error) {
    const int n = v.probeCount(), cols = atlasColumns(n), rows = (n + cols - 1) / cols;
    const int wi = ProbeVolume::kIrradianceTexels + 2, wd = ProbeVolume::kDistanceTexels + 2;
    OIIO::ImageSpec irr(cols * wi, rows * wi, 3, OIIO::TypeDesc::FLOAT);
    irr.channelnames = {"R", "G", "B"};
    irr.attribute("oiio:subimagename", "irradiance");
    OIIO::ImageSpec dist(cols * wd, rows * wd, 2, OIIO::TypeDesc::FLOAT);
    dist.channelnames = {"mean", "meanSquare"};
    dist.attribute("oiio:subimagename", "distance");
    for (OIIO::ImageSpec* s : {&irr, &dist}) {
        s->attribute("compression", "zip");
        setGrid(*s, v);
        s->full_x = s->full_y = 0;
        s->full_width = irr.width;
        s->full_height = irr.height;
    }
    std::vector<float> a(size_t(irr.width) * size_t(irr.height) * 3, 0.0f);
    std::vector<float> b(size_t(dist.width) * size_t(dist.height) * 2, 0.0f);
    for (int p = 0; p < n; ++p) {
        const int cx = p % cols, cy = p / cols;
        for (int y = 0; y < wi; ++y)
            for (int x = 0; x < wi; ++x) {
                const glm::vec3 e = v.irradiance[size_t(p) * size_t(wi * wi) + size_t(y * wi + x)];
                float* o = &a[3 * (size_t(cy * wi + y) * size_t(irr.width) + size_t(cx * wi + x))];
                o[0] = e.r;
                o[1] = e.g;
                o[2] = e.b;
            }
        for (int y = 0; y < wd; ++y)
            for (int x = 0; x < wd; ++x) {
                const glm::vec2 d = v.distance[size_t(p) * size_t(wd * wd) + size_t(y * wd + x)];
                float* o = &b[2 * (size_t(cy * wd + y) * size_t(dist.width) + size_t(cx * wd + x))];
                o[0] = d.x;
                o[1] = d.y;
            }
    }
    auto out = OIIO::ImageOutput::create(path);
    const OIIO::ImageSpec specs[2] = {irr, dist};
    if (!out || !out->supports("multiimage") || !out->open(path, 2, specs)) {
        error = out ? out->geterror() : OIIO::geterror();
        return false;
    }
    const bool ok = out->write_image(OIIO::TypeDesc::FLOAT, a.data()) &&
                    out->open(path, dist, OIIO::ImageOutput::AppendSubimage) &&
                    out->write_image(OIIO::TypeDesc::FLOAT, b.data()) && out->close();
    if (!ok) error = out->geterror();
    return ok;
}

bool readProbes(const std::string& path, ProbeVolume& v, std::string& error) {
    if (!detail::exrHeadersFit(path, error)) return false;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        error = OIIO::geterror();
        return false;
    }
    const OIIO::ImageSpec irr = in->spec();
    ProbeAttributes at{};
    AtlasPixels px;
    return findProbeAttributes(irr, at, error) && readGrid(at, v, error) &&
           irradianceFitsGrid(at, irr, v, error) && readBakeRecord(irr, v, error) &&
           readProbeStates(at, v, error) && readAtlasPixels(*in, irr, v, px, error) &&
           unpackAtlases(px, v, error);
}

void roundAsStored(ProbeVolume& volume) {
    // Through a volatile float: GCC 12.2's SLP vectoriser at -O2/-O3 rounds only four of the
    // six values when they are written as glm::dvec3(glm::vec3(...)) or as a plain loop
    // (spacing.y and .z come out unrounded; reproduced outside the project).
    for (glm::dvec3* v : {&volume.origin, &volume.spacing})
        for (int a = 0; a < 3; ++a) {
            volatile float stored = float((*v)[a]);
            (*v)[a] = stored;
        }
}

} // namespace dhdr
