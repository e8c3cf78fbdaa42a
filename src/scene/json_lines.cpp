#include "scene/json_lines.h"

#include <algorithm>
#include <vector>

namespace sdfvj {

namespace {

struct Frame {
    bool object = false;
    std::string pointer;      // this container's own pointer
    std::string key;          // object: the current member's key
    size_t index = 0;         // array: the current element
    bool expectKey = true;    // object: the next string is a key
    bool elementSeen = false; // array: the current element is recorded
};

bool IsDelimiter(char c) {
    return c == ',' || c == ']' || c == '}' || c == ':' || c == '"' || c == '[' || c == '{' || c == ' ' ||
           c == '\t' || c == '\r' || c == '\n';
}

}  // namespace

int LineOfOffset(const std::string& text, size_t offset) {
    offset = std::min(offset, text.size());
    return 1 + (int)std::count(text.begin(), text.begin() + (long)offset, '\n');
}

bool ScanJsonLayout(const std::string& text, size_t begin, size_t end, int maxDepth, JsonLayout* layout) {
    end = std::min(end, text.size());
    std::vector<Frame> stack;
    bool rootSeen = false;
    // A value starts at `at`: records it under the pointer the enclosing container gives it.
    // Returns the value's pointer.
    auto valueStart = [&](size_t at) -> std::string {
        if (stack.empty()) {
            if (!rootSeen) layout->offsets.emplace("", at);
            rootSeen = true;
            return "";
        }
        Frame& f = stack.back();
        if (f.object) return f.pointer + "/" + f.key;  // recorded at its key
        std::string p = f.pointer + "/" + std::to_string(f.index);
        if (!f.elementSeen) layout->offsets.emplace(p, at);
        f.elementSeen = true;
        return p;
    };
    size_t i = begin;
    while (i < end) {
        const char c = text[i];
        if (c == '{' || c == '[') {
            std::string p = valueStart(i);
            if ((int)stack.size() >= maxDepth) {
                layout->tooDeepAt = i;
                return false;
            }
            Frame f;
            f.object = c == '{';
            f.pointer = std::move(p);
            stack.push_back(std::move(f));
            ++i;
        } else if (c == '}' || c == ']') {
            if (!stack.empty()) stack.pop_back();
            ++i;
        } else if (c == '"') {
            size_t j = i + 1;
            while (j < end && text[j] != '"') j += text[j] == '\\' ? 2 : 1;
            const size_t close = std::min(j, end);
            if (!stack.empty() && stack.back().object && stack.back().expectKey) {
                Frame& f = stack.back();
                f.key = text.substr(i + 1, close - (i + 1));
                f.expectKey = false;
                layout->offsets.emplace(f.pointer + "/" + f.key, i);
            } else {
                valueStart(i);
            }
            i = close + 1;
        } else if (c == ':') {
            ++i;
        } else if (c == ',') {
            if (!stack.empty()) {
                Frame& f = stack.back();
                if (f.object) f.expectKey = true;
                else { ++f.index; f.elementSeen = false; }
            }
            ++i;
        } else if (c == ' ' || c == '\t' || c == '\r' || c == '\n') {
            ++i;
        } else {  // a literal or a number (or junk nlohmann will report)
            valueStart(i);
            while (i < end && !IsDelimiter(text[i])) ++i;
        }
    }
    return true;
}

int LineOfPointer(const std::string& text, const JsonLayout& layout, std::string pointer, int fallbackLine) {
    while (true) {
        if (auto it = layout.offsets.find(pointer); it != layout.offsets.end()) return LineOfOffset(text, it->second);
        if (pointer.empty()) return fallbackLine;
        const size_t slash = pointer.rfind('/');
        pointer.erase(slash == std::string::npos ? 0 : slash);
    }
}

std::string JsonErrorReason(const std::string& what) {
    std::string w = what;
    if (size_t p = w.find("] "); p != std::string::npos && w.rfind("[json.exception", 0) == 0) w = w.substr(p + 2);
    // "parse error at line 1, column 5: syntax error ..." -> "syntax error ..."
    if (w.rfind("parse error", 0) == 0)
        if (size_t p = w.find(": "); p != std::string::npos) w = w.substr(p + 2);
    return w;
}

}  // namespace sdfvj
