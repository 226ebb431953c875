#include "sequence_stats.h"

#include "../common/tool.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <dhdr/tonemap/adaptation.h>
#include <fstream>
#include <nlohmann/json.hpp>

namespace dhdr::app {

namespace {

std::string number(double v) {
    char text[40];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
}

} // namespace

std::string toJson(const SequenceStats& stats) {
    std::string json = "{\n  \"fps\": " + number(stats.fps) +
                       ",\n  \"adapt\": " + (stats.adapt ? "true" : "false") +
                       ",\n  \"metering\": " + nlohmann::json(stats.metering).dump() +
                       ",\n  \"frames\": [\n";
    for (size_t i = 0; i < stats.frames.size(); ++i) {
        const FrameLuminance& f = stats.frames[i];
        json += "    {\"frame\": " + std::to_string(f.frame) +
                ", \"file\": " + nlohmann::json(f.file).dump() +
                ", \"logAverage\": " + number(f.logAverage) +
                ", \"adapted\": " + number(f.adapted) + "}" +
                (i + 1 < stats.frames.size() ? ",\n" : "\n");
    }
    return json + "  ]\n}\n";
}

bool readSequenceStats(const std::string& path, SequenceStats& stats, std::string& error) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = path + ": cannot be read";
        return false;
    }
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        error = path + ": not JSON (" + e.what() + ")";
        return false;
    }
    // Every value the file must hold, checked before any is used.
    const auto positive = [](const nlohmann::json& v) {
        return v.is_number() && std::isfinite(v.get<double>()) && v.get<double>() > 0.0;
    };
    if (!doc.is_object() || !doc.contains("frames") || !doc["frames"].is_array() ||
        !doc.contains("metering") || !doc["metering"].is_string() || !doc.contains("adapt") ||
        !doc["adapt"].is_boolean() || !doc.contains("fps") || !positive(doc["fps"])) {
        error = path + ": not a dhdr-tonemap statistics file (it needs fps, adapt, metering "
                       "and frames)";
        return false;
    }
    stats = {};
    stats.fps = doc["fps"].get<double>();
    stats.adapt = doc["adapt"].get<bool>();
    stats.metering = doc["metering"].get<std::string>();
    for (const nlohmann::json& f : doc["frames"]) {
        if (!f.is_object() || !f.contains("frame") || !f["frame"].is_number_integer() ||
            !f.contains("logAverage") || !positive(f["logAverage"]) || !f.contains("adapted") ||
            !positive(f["adapted"])) {
            error = path + ": frame " + std::to_string(stats.frames.size()) +
                    " needs an integer frame and positive logAverage and adapted";
            return false;
        }
        FrameLuminance row;
        row.frame = f["frame"].get<int>();
        row.file = f.contains("file") && f["file"].is_string() ? f["file"].get<std::string>()
                                                               : std::string();
        row.logAverage = f["logAverage"].get<double>();
        row.adapted = f["adapted"].get<double>();
        stats.frames.push_back(row);
    }
    return true;
}

int scanStatistics(const Tool& tool, const std::vector<std::string>& files,
                   const AdaptationParams& adaptation, const std::string& out) {
    SequenceStats all;
    std::vector<std::string> from; // the file each frame came from
    for (const std::string& path : files) {
        SequenceStats chunk;
        if (std::string error; !readSequenceStats(path, chunk, error)) return tool.fail(error);
        if (from.empty())
            all.metering = chunk.metering;
        else if (chunk.metering != all.metering)
            return tool.fail(path + ": metered with " + chunk.metering + ", but " + files[0] +
                             " with " + all.metering + "; meter every chunk the same way");
        for (const FrameLuminance& f : chunk.frames) {
            all.frames.push_back(f);
            from.push_back(path);
        }
    }
    if (all.frames.empty()) return tool.fail("the statistics files hold no frames");
    std::vector<size_t> order(all.frames.size());
    for (size_t i = 0; i < order.size(); ++i)
        order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return all.frames[a].frame < all.frames[b].frame; });
    std::vector<FrameLuminance> sorted;
    for (size_t k = 0; k < order.size(); ++k) {
        if (k > 0 && all.frames[order[k]].frame == all.frames[order[k - 1]].frame)
            return tool.fail("frame " + std::to_string(all.frames[order[k]].frame) +
                             " is in both " + from[order[k - 1]] + " and " + from[order[k]]);
        sorted.push_back(all.frames[order[k]]);
    }
    all.frames = sorted;
    const int gaps =
        all.frames.back().frame - all.frames.front().frame + 1 - int(all.frames.size());
    if (gaps > 0)
        tool.warn(std::to_string(gaps) +
                  " frames of the range are missing from the statistics; adaptation steps "
                  "over them as if they were not there");
    std::vector<double> measured;
    for (const FrameLuminance& f : all.frames)
        measured.push_back(f.logAverage);
    const std::vector<double> adapted = adaptLuminance(measured, adaptation);
    for (size_t i = 0; i < all.frames.size(); ++i)
        all.frames[i].adapted = adapted[i];
    all.fps = adaptation.fps;
    all.adapt = true;
    tool.info("scanned " + std::to_string(all.frames.size()) + " frames, " +
              std::to_string(all.frames.front().frame) + " to " +
              std::to_string(all.frames.back().frame));
    return tool.writeText(toJson(all), out) ? kExitSuccess : kExitFailure;
}

} // namespace dhdr::app
