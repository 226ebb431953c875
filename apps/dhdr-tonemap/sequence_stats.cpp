#include "sequence_stats.h"

#include <cmath>
#include <cstdio>
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

} // namespace dhdr::app
