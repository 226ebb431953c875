#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <cctype>
#include <dhdr/io/banded_read.h>
#include <dhdr/io/errors.h>
#include <dhdr/io/exr_header.h>
#include <dhdr/io/layers.h>
#include <dhdr/io/pixel_limit.h>
#include <filesystem>
#include <map>
#include <memory>

namespace dhdr {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

// The last '.'-separated component of a layer name.
std::string lastComponent(const std::string& name) {
    const size_t dot = name.find_last_of('.');
    return dot == std::string::npos ? name : name.substr(dot + 1);
}

// R, G, B, A as channel suffixes: the usual letters, either case, and Nuke's long names.
int componentIndex(const std::string& suffix) {
    static const std::map<std::string, int> names = {{"r", 0}, {"red", 0},  {"g", 1}, {"green", 1},
                                                     {"b", 2}, {"blue", 2}, {"a", 3}, {"alpha", 3}};
    const auto it = names.find(lower(suffix));
    return it == names.end() ? -1 : it->second;
}

std::string layerList(const std::vector<ColourLayer>& layers) {
    std::string list;
    for (const ColourLayer& l : layers)
        list += (list.empty() ? "" : ", ") + (l.name().empty() ? "(unnamed R,G,B)" : l.name());
    return list.empty() ? "none" : list;
}

} // namespace

std::string ColourLayer::name() const {
    if (part.empty()) return prefix;
    if (prefix.empty()) return part;
    return part + "." + prefix;
}

bool listColourLayers(const std::string& path, std::vector<ColourLayer>& layers,
                      std::string& error) {
    layers.clear();
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
    if (!in) {
        error = OIIO::geterror();
        return false;
    }
    const bool multiPart = in->seek_subimage(1, 0);
    for (int s = 0; in->seek_subimage(s, 0); ++s) {
        const OIIO::ImageSpec& spec = in->spec();
        const std::string part = multiPart ? std::string(spec.get_string_attribute(
                                                 "oiio:subimagename", "part" + std::to_string(s)))
                                           : std::string();
        // Layers in the order their first channel appears.
        std::vector<ColourLayer> found;
        for (int c = 0; c < spec.nchannels; ++c) {
            const std::string& channel = spec.channelnames[size_t(c)];
            const size_t dot = channel.find_last_of('.');
            const std::string prefix = dot == std::string::npos ? "" : channel.substr(0, dot);
            const int k =
                componentIndex(dot == std::string::npos ? channel : channel.substr(dot + 1));
            if (k < 0) continue;
            auto it = std::find_if(found.begin(), found.end(),
                                   [&](const ColourLayer& l) { return l.prefix == prefix; });
            if (it == found.end()) {
                ColourLayer l;
                l.subimage = s;
                l.part = part;
                l.prefix = prefix;
                l.partChannels = spec.channelnames;
                l.width = spec.width;
                l.height = spec.height;
                l.depth = spec.depth;
                found.push_back(l);
                it = found.end() - 1;
            }
            if (it->rgba[k] < 0) it->rgba[k] = c;
        }
        for (const ColourLayer& l : found)
            if (l.rgba[0] >= 0 && l.rgba[1] >= 0 && l.rgba[2] >= 0) layers.push_back(l);
    }
    return true;
}

bool chooseColourLayer(const std::vector<ColourLayer>& layers, const std::string& wanted,
                       ColourLayer& chosen, std::string& error) {
    // The layers that pass `test`; true when exactly one does.
    auto pick = [&](auto test, std::vector<const ColourLayer*>& matches) {
        matches.clear();
        for (const ColourLayer& l : layers)
            if (test(l)) matches.push_back(&l);
        if (matches.size() == 1) chosen = *matches[0];
        return matches.size() == 1;
    };
    std::vector<const ColourLayer*> matches;
    if (!wanted.empty()) {
        const std::string w = lower(wanted);
        if (pick([&](const ColourLayer& l) { return l.name() == wanted; }, matches) ||
            pick([&](const ColourLayer& l) { return l.prefix.empty() && l.part == wanted; },
                 matches) ||
            pick([&](const ColourLayer& l) { return l.prefix == wanted; }, matches) ||
            pick([&](const ColourLayer& l) { return lower(lastComponent(l.name())) == w; },
                 matches))
            return true;
        error =
            matches.size() > 1
                ? "more than one layer is called '" + wanted + "': " + layerList(layers)
                : "no colour layer or part '" + wanted + "' (it has: " + layerList(layers) + ")";
        return false;
    }
    if (layers.empty()) {
        error = "no R, G, B channels in any layer or part";
        return false;
    }
    if (pick([](const ColourLayer& l) { return l.name().empty(); }, matches)) return true;
    const bool conventional =
        pick(
            [](const ColourLayer& l) {
                const std::string last = lower(lastComponent(l.name()));
                return last == "combined" || last == "rgba" || last == "beauty";
            },
            matches) ||
        (matches.empty() && layers.size() == 1 && (chosen = layers[0], true));
    if (conventional) return true;
    error = "cannot tell which layer is the image (layers: " + layerList(layers) +
            "); choose one with --layer NAME";
    return false;
}

namespace {

// The channels of `layer` in the order a tool works on them (R, G, B, A, then the others
// with `keepOthers`), as indices into the part's channels.
std::vector<int> channelOrder(const ColourLayer& layer, bool keepOthers) {
    const int nrgba = layer.rgba[3] >= 0 ? 4 : 3;
    std::vector<int> order(layer.rgba, layer.rgba + nrgba);
    if (keepOthers)
        for (int c = 0; c < int(layer.partChannels.size()); ++c)
            if (std::find(order.begin(), order.end(), c) == order.end()) order.push_back(c);
    return order;
}

} // namespace

bool ColourStripReader::open(const std::string& path, const ColourLayer& layer, bool keepOthers,
                             int nthreads, std::string& error) {
    m_order = channelOrder(layer, keepOthers);
    const int chbegin = *std::min_element(m_order.begin(), m_order.end());
    const int chend = *std::max_element(m_order.begin(), m_order.end()) + 1;
    if (!m_reader.open(path, layer.subimage, chbegin, chend, nthreads, error)) return false;
    for (int& c : m_order)
        c -= chbegin;
    m_identity = int(m_order.size()) == chend - chbegin;
    for (size_t i = 0; i < m_order.size(); ++i)
        m_identity = m_identity && m_order[i] == int(i);
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
    m_formats.clear();
    if (in && in->seek_subimage(layer.subimage, 0))
        for (int c : m_order)
            m_formats.push_back(in->spec().channelformat(c + chbegin));
    m_alpha = layer.rgba[3] >= 0 ? 3 : -1;
    m_spec = m_reader.spec();
    m_spec.nchannels = int(m_order.size());
    m_spec.channelnames.clear();
    for (int c : m_order)
        m_spec.channelnames.push_back(m_reader.spec().channelnames[size_t(c)]);
    m_spec.alpha_channel = m_alpha;
    const auto z = std::find(m_spec.channelnames.begin(), m_spec.channelnames.end(), "Z");
    m_spec.z_channel = z == m_spec.channelnames.end() ? -1 : int(z - m_spec.channelnames.begin());
    return true;
}

bool ColourStripReader::read(int ybegin, int yend, OIIO::ImageBuf& strip, std::string& error) {
    if (m_identity) {
        if (!m_reader.read(ybegin, yend, strip, error)) return false;
        strip.specmod().alpha_channel = m_alpha;
        return true;
    }
    if (!m_reader.read(ybegin, yend, m_raw, error)) return false;
    OIIO::ImageSpec rows = m_spec;
    rows.y = m_raw.spec().y;
    rows.height = m_raw.spec().height;
    if (!(strip.initialized() && strip.localpixels() && strip.spec().width == rows.width &&
          strip.spec().height == rows.height && strip.nchannels() == rows.nchannels &&
          strip.spec().format == OIIO::TypeDesc::FLOAT))
        strip.reset(rows, OIIO::InitializePixels::No);
    strip.set_origin(rows.x, rows.y);
    const size_t inCh = size_t(m_raw.nchannels()), outCh = m_order.size();
    const auto* src = static_cast<const float*>(m_raw.localpixels());
    auto* dst = static_cast<float*>(strip.localpixels());
    for (size_t i = 0, n = size_t(rows.width) * size_t(rows.height); i < n; ++i)
        for (size_t c = 0; c < outCh; ++c)
            dst[i * outCh + c] = src[i * inCh + size_t(m_order[c])];
    return true;
}

bool readColourLayer(const std::string& path, const ColourLayer& layer, bool keepOthers,
                     int nthreads, OIIO::ImageBuf& image, std::vector<OIIO::TypeDesc>& formats,
                     std::string& error) {
    const int nrgba = layer.rgba[3] >= 0 ? 4 : 3;
    const std::vector<int> order = channelOrder(layer, keepOthers);
    const int chbegin = *std::min_element(order.begin(), order.end());
    const int chend = *std::max_element(order.begin(), order.end()) + 1;
    if (!readBanded(path, image, chbegin, chend, nthreads, error, layer.subimage)) return false;

    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
    formats.clear();
    if (in && in->seek_subimage(layer.subimage, 0))
        for (int c : order)
            formats.push_back(in->spec().channelformat(c));
    bool identity = true;
    for (size_t i = 0; i < order.size(); ++i)
        identity = identity && order[i] - chbegin == int(i);
    if (identity && int(order.size()) == image.nchannels()) {
        image.specmod().alpha_channel = nrgba == 4 ? 3 : -1;
        return true;
    }

    std::vector<int> local;
    for (int c : order)
        local.push_back(c - chbegin);
    OIIO::ImageBuf reordered;
    if (!OIIO::ImageBufAlgo::channels(reordered, image, int(local.size()), local.data(), {}, {},
                                      false, nthreads)) {
        error = reordered.geterror();
        return false;
    }
    OIIO::ImageSpec& spec = reordered.specmod();
    spec.alpha_channel = nrgba == 4 ? 3 : -1;
    const std::vector<std::string>& names = spec.channelnames;
    const auto z = std::find(names.begin(), names.end(), "Z");
    spec.z_channel = z == names.end() ? -1 : int(z - names.begin());
    image = std::move(reordered);
    return true;
}

bool findColourLayer(const std::string& path, const std::string& wanted, ColourLayer& chosen,
                     size_t& layerCount, std::string& error) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
        error = path + ": no such file";
        return false;
    }
    std::string why;
    // Before OpenEXR allocates what its headers claim.
    if (!detail::exrHeadersFit(path, why)) {
        error = path + ": " + why;
        return false;
    }
    std::vector<ColourLayer> layers;
    if (!listColourLayers(path, layers, why)) {
        error = cannotRead(path, why);
        return false;
    }
    layerCount = layers.size();
    if (!chooseColourLayer(layers, wanted, chosen, why)) {
        error = path + ": " + why;
        return false;
    }
    if (const std::string e = pixelLimitError(chosen.width, chosen.height, chosen.depth);
        !e.empty()) {
        error = path + ": " + e;
        return false;
    }
    return true;
}

} // namespace dhdr
