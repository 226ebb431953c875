#include "exr_spec_header.h"

#include <Imath/ImathBox.h>
#include <Imath/ImathMatrix.h>
#include <Imath/ImathVec.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfStringVectorAttribute.h>
#include <OpenEXR/ImfVecAttribute.h>
#include <algorithm>
#include <cctype>
#include <ctime>
#include <thread>
#include <vector>

namespace dhdr::detail {

namespace {

bool startsWith(const std::string& s, const char* prefix) {
    return s.rfind(prefix, 0) == 0;
}

// Attributes handled apart from the loop: OpenImageIO's own, and the standard ones.
bool skipped(const std::string& name) {
    return startsWith(name, "oiio:") || startsWith(name, "openexr:") || name == "compression" ||
           name == "DateTime" || name == "PixelAspectRatio" || name == "screenWindowCenter" ||
           name == "screenWindowWidth";
}

// The attribute types the loop below writes.
enum class Kind { String, StringList, Matrix, Vec3, Vec2, Float, Double, Int, Other };

Kind kindOf(OIIO::TypeDesc t) {
    if (t == OIIO::TypeString) return Kind::String;
    if (t.basetype == OIIO::TypeDesc::STRING) return Kind::StringList;
    if (t == OIIO::TypeMatrix44) return Kind::Matrix;
    if (t.basetype == OIIO::TypeDesc::FLOAT && t.basevalues() == 3) return Kind::Vec3;
    if (t.basetype == OIIO::TypeDesc::FLOAT && t.basevalues() == 2) return Kind::Vec2;
    if (t == OIIO::TypeFloat) return Kind::Float;
    if (t == OIIO::TypeDesc::DOUBLE) return Kind::Double;
    if (t == OIIO::TypeInt) return Kind::Int;
    return Kind::Other;
}

void insert(Imf::Header& header, const OIIO::ParamValue& p) {
    const std::string name = p.name().string();
    const OIIO::TypeDesc t = p.type();
    switch (kindOf(t)) {
    case Kind::String:
        header.insert(name, Imf::StringAttribute(p.get_string()));
        break;
    case Kind::StringList: {
        std::vector<std::string> list;
        for (size_t i = 0; i < size_t(p.nvalues()) * t.numelements(); ++i)
            list.emplace_back(static_cast<const OIIO::ustring*>(p.data())[i].string());
        header.insert(name, Imf::StringVectorAttribute(list));
        break;
    }
    case Kind::Matrix: {
        const float* m = static_cast<const float*>(p.data());
        header.insert(name, Imf::M44fAttribute(Imath::M44f(m[0], m[1], m[2], m[3], m[4], m[5], m[6],
                                                           m[7], m[8], m[9], m[10], m[11], m[12],
                                                           m[13], m[14], m[15])));
        break;
    }
    case Kind::Vec3: {
        const float* v = static_cast<const float*>(p.data());
        header.insert(name, Imf::V3fAttribute(Imath::V3f(v[0], v[1], v[2])));
        break;
    }
    case Kind::Vec2: {
        const float* v = static_cast<const float*>(p.data());
        header.insert(name, Imf::V2fAttribute(Imath::V2f(v[0], v[1])));
        break;
    }
    case Kind::Float:
        header.insert(name, Imf::FloatAttribute(p.get_float()));
        break;
    case Kind::Double:
        // A G-buffer's time (gbuffer_time.h): every bit of the double kept.
        header.insert(name, Imf::DoubleAttribute(*static_cast<const double*>(p.data())));
        break;
    case Kind::Int:
        header.insert(name, Imf::IntAttribute(p.get_int()));
        break;
    case Kind::Other:
        break;
    }
}

} // namespace

Imf::Header exrHeaderFromSpec(const OIIO::ImageSpec& spec) {
    const Imath::Box2i data(Imath::V2i(spec.x, spec.y),
                            Imath::V2i(spec.x + spec.width - 1, spec.y + spec.height - 1));
    const Imath::Box2i display(
        Imath::V2i(spec.full_x, spec.full_y),
        Imath::V2i(spec.full_x + spec.full_width - 1, spec.full_y + spec.full_height - 1));
    Imf::Header header(display, data);
    header.pixelAspectRatio() = spec.get_float_attribute("PixelAspectRatio", 1.0f);
    header.screenWindowWidth() = spec.get_float_attribute("screenWindowWidth", 1.0f);
    if (const OIIO::ParamValue* c = spec.find_attribute("screenWindowCenter", OIIO::TypeFloat2)) {
        const float* v = static_cast<const float*>(c->data());
        header.screenWindowCenter() = Imath::V2f(v[0], v[1]);
    }
    // OpenImageIO keeps a file's date in DateTime and writes it as OpenEXR's capDate.
    std::string date = spec.get_string_attribute("DateTime");
    if (date.empty()) {
        const std::time_t now = std::time(nullptr);
        char text[32];
        std::strftime(text, sizeof text, "%Y:%m:%d %H:%M:%S", std::localtime(&now));
        date = text;
    }
    header.insert("capDate", Imf::StringAttribute(date));
    for (const OIIO::ParamValue& p : spec.extra_attribs)
        if (!skipped(p.name().string())) insert(header, p);
    return header;
}

bool exrHeaderKeepsEverything(const OIIO::ImageSpec& spec, std::string& why) {
    // Names OpenImageIO writes under another name or reads a meaning into.
    static const char* const kRenamed[] = {"ImageDescription", "Copyright",   "ExposureTime",
                                           "FNumber",          "Artist",      "DocumentName",
                                           "HostComputer",     "Orientation", "ICCProfile"};
    for (const OIIO::ParamValue& p : spec.extra_attribs) {
        const std::string name = p.name().string();
        if (skipped(name)) continue;
        const bool renamed =
            std::find(std::begin(kRenamed), std::end(kRenamed), name) != std::end(kRenamed);
        const bool interpreted = startsWith(name, "Exif:") || startsWith(name, "IPTC:") ||
                                 startsWith(name, "smpte:") || startsWith(name, "XMP:") ||
                                 startsWith(name, "GPS:") || startsWith(name, "exr:");
        if (renamed || interpreted || kindOf(p.type()) == Kind::Other) {
            why = "attribute '" + name + "' (" + p.type().c_str() + ")";
            return false;
        }
    }
    return true;
}

bool exrCompression(const std::string& name, Imf::Compression& compression, int& level) {
    std::string base = name;
    level = -1;
    if (const size_t colon = name.find(':'); colon != std::string::npos) {
        base = name.substr(0, colon);
        const std::string digits = name.substr(colon + 1);
        if (digits.empty() || digits.size() > 3 ||
            !std::all_of(digits.begin(), digits.end(), [](char c) { return std::isdigit(c); }))
            return false;
        level = std::stoi(digits);
    }
    static const struct {
        const char* name;
        Imf::Compression compression;
        bool levelled; // takes ":N"
    } kNames[] = {{"none", Imf::NO_COMPRESSION, false},  {"rle", Imf::RLE_COMPRESSION, false},
                  {"zips", Imf::ZIPS_COMPRESSION, true}, {"zip", Imf::ZIP_COMPRESSION, true},
                  {"piz", Imf::PIZ_COMPRESSION, false},  {"pxr24", Imf::PXR24_COMPRESSION, false},
                  {"b44", Imf::B44_COMPRESSION, false},  {"b44a", Imf::B44A_COMPRESSION, false},
                  {"dwaa", Imf::DWAA_COMPRESSION, true}, {"dwab", Imf::DWAB_COMPRESSION, true}};
    for (const auto& n : kNames)
        if (base == n.name) {
            if (level >= 0 && !n.levelled) return false;
            if (level >= 0 && n.compression <= Imf::ZIP_COMPRESSION && (level < 1 || level > 9))
                return false;
            compression = n.compression;
            return true;
        }
    return false;
}

int exrThreads() {
    int threads = 0;
    OIIO::getattribute("exr_threads", threads);
    if (threads < 0) return 0;
    return threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
}

} // namespace dhdr::detail
