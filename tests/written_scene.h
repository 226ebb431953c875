// glTF documents a library test writes and loads (test_animation, test_instancing): a scratch
// folder for the program's files, removed when it ends, and loadScene of a written document.
#pragma once

#include "animation_writer.h"

#include <dhdr/deferred/scene/scene.h>
#include <filesystem>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <string>

namespace dhdr::test {

inline std::string scratch(const std::string& name) {
    struct Folder {
        std::filesystem::path path;
        Folder() {
            char pattern[] = "/tmp/dhdr_written_XXXXXX";
            path = mkdtemp(pattern);
        }
        ~Folder() { std::filesystem::remove_all(path); }
    };
    static const Folder dir;
    return (dir.path / name).string();
}

// `doc` written to the scratch folder as `name` and loaded; a failure to load fails the test.
inline Scene load(const nlohmann::json& doc, const std::string& name) {
    writeJson(scratch(name), doc);
    Scene scene;
    std::string error;
    EXPECT_TRUE(loadScene(scratch(name), scene, error)) << error;
    return scene;
}

} // namespace dhdr::test
