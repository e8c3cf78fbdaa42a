// JSON pre-scan for scene headers and presets (scene module internal, not part of scene.h).
//
// Runs before nlohmann parses the text and gives the checks two things it cannot:
//   - a nesting limit: `[[[[...` 100000 deep is refused here with its line, so no parser,
//     destructor or dump ever walks it;
//   - the line of every value: "/INPUTS/0/LABEL" -> the line of `"LABEL"` inside the first
//     input, so a wrong-typed field is reported where it is, not at the first "LABEL" in the file.
// The scan never fails on bad JSON: it records what it can and nlohmann reports the syntax error.
#pragma once
#include <cstddef>
#include <map>
#include <string>

namespace sdfvj {

constexpr int kMaxJsonDepth = 64;                  // deeper headers/presets are refused
constexpr size_t kMaxJsonBytes = size_t(1) << 20;  // 1 MiB of header or preset at most

struct JsonLayout {
    // JSON pointer of each value -> byte offset in the scanned text. Object members point at
    // their key, array elements at their first character. "" is the outermost value.
    std::map<std::string, size_t> offsets;
    size_t tooDeepAt = std::string::npos;  // offset of the first bracket past maxDepth
};

// Scans text[begin, end). Returns false when nesting exceeds maxDepth (layout->tooDeepAt says
// where); the scan stops there.
bool ScanJsonLayout(const std::string& text, size_t begin, size_t end, int maxDepth, JsonLayout* layout);

// 1-based line of a byte offset in text.
int LineOfOffset(const std::string& text, size_t offset);

// Line of `pointer`, else of its nearest recorded parent, else fallbackLine.
int LineOfPointer(const std::string& text, const JsonLayout& layout, std::string pointer, int fallbackLine);

// nlohmann's exception text without its "[json.exception...] parse error at line 1, column 5"
// prefix (those positions are relative to the header, not the file).
std::string JsonErrorReason(const std::string& what);

}  // namespace sdfvj
