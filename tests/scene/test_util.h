// Helpers for the scene tests: files in a per-process temp folder, and the error-line check.
#pragma once
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <catch2/catch.hpp>

namespace scene_test {

inline std::filesystem::path TempDir() {
    static const std::filesystem::path dir = [] {
        auto d = std::filesystem::temp_directory_path() / ("sdfvj-scene-test-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir;
}

inline std::string WriteTemp(const std::string& name, const std::string& content) {
    const std::filesystem::path p = TempDir() / name;
    std::ofstream(p, std::ios::binary) << content;
    return p.string();
}

// `text` with the first `from` replaced by `to`; fails the test when `from` is not there.
inline std::string With(std::string text, const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    return text.replace(at, from.size(), to);
}

// The project's error shape: "path:LINE: what is wrong, ... expected ...".
inline void CheckError(const std::string& error, const std::string& path, int line, const std::string& names) {
    INFO("error: " << error);
    CHECK(error.rfind(path + ":" + std::to_string(line) + ": ", 0) == 0);
    CHECK(error.find(names) != std::string::npos);
    CHECK(error.find("expected") != std::string::npos);
}

}  // namespace scene_test
