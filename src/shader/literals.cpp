#include "shader/literals.h"

#include <cctype>
#include <charconv>

namespace sdfvj {

namespace {

bool IsWordChar(char c) { return std::isalnum((unsigned char)c) || c == '_'; }
bool IsDigit(char c) { return c >= '0' && c <= '9'; }

// A GLSL numeric literal starting at i (digits, '.', exponent, suffix): its end, and whether it is
// a float literal (single precision) that can be lifted.
size_t ScanNumber(const std::string& s, size_t i, bool* liftableFloat) {
    size_t k = i;
    bool dot = false, exponent = false;
    if (s.compare(k, 2, "0x") == 0 || s.compare(k, 2, "0X") == 0) {   // hex integer
        k += 2;
        while (k < s.size() && std::isxdigit((unsigned char)s[k])) ++k;
    } else {
        while (k < s.size() && IsDigit(s[k])) ++k;
        if (k < s.size() && s[k] == '.') {
            dot = true;
            ++k;
            while (k < s.size() && IsDigit(s[k])) ++k;
        }
        if (k < s.size() && (s[k] == 'e' || s[k] == 'E')) {
            size_t e = k + 1;
            if (e < s.size() && (s[e] == '+' || s[e] == '-')) ++e;
            if (e < s.size() && IsDigit(s[e])) {
                exponent = true;
                k = e;
                while (k < s.size() && IsDigit(s[k])) ++k;
            }
        }
    }
    bool isDouble = false;
    if (s.compare(k, 2, "lf") == 0 || s.compare(k, 2, "LF") == 0) {
        isDouble = true;
        k += 2;
    } else if (k < s.size() && (s[k] == 'f' || s[k] == 'F' || s[k] == 'u' || s[k] == 'U')) {
        ++k;
    }
    // Something glued on (a swizzle-like name, a malformed token): leave the whole word alone.
    const bool clean = k >= s.size() || !(IsWordChar(s[k]) || s[k] == '.');
    while (k < s.size() && (IsWordChar(s[k]) || s[k] == '.')) ++k;
    *liftableFloat = clean && (dot || exponent) && !isDouble;
    return k;
}

// Walks `text` and calls visit(begin, end) for every liftable literal, in order, until it returns false.
template <class Visit>
void ForEachLiftable(const std::string& s, Visit visit) {
    int depth = 0;             // brace depth: > 0 inside a function body
    bool inConst = false;      // inside a `const` declaration, up to its ';'
    bool lineStart = true;     // only spaces so far on this line
    for (size_t i = 0; i < s.size();) {
        const char c = s[i];
        if (s.compare(i, 2, "//") == 0) {
            i = s.find('\n', i);
            if (i == std::string::npos) return;
            continue;
        }
        if (s.compare(i, 2, "/*") == 0) {
            i = s.find("*/", i + 2);
            if (i == std::string::npos) return;
            i += 2;
            continue;
        }
        if (c == '\n') {
            lineStart = true;
            ++i;
            continue;
        }
        if (c == ' ' || c == '\t' || c == '\r') {
            ++i;
            continue;
        }
        if (c == '#' && lineStart) {   // a preprocessor line, with its continuations
            while (i < s.size() && s[i] != '\n') {
                if (s[i] == '\\' && i + 1 < s.size() && s[i + 1] == '\n') ++i;
                ++i;
            }
            continue;
        }
        lineStart = false;
        if (c == '{') ++depth;
        else if (c == '}') depth = depth > 0 ? depth - 1 : 0;
        else if (c == ';') inConst = false;
        if (IsWordChar(c) && !IsDigit(c)) {   // an identifier or keyword
            size_t k = i;
            while (k < s.size() && IsWordChar(s[k])) ++k;
            if (s.compare(i, k - i, "const") == 0) inConst = true;
            i = k;
            continue;
        }
        if (IsDigit(c) || (c == '.' && i + 1 < s.size() && IsDigit(s[i + 1]))) {
            bool liftable = false;
            const size_t end = ScanNumber(s, i, &liftable);
            if (liftable && depth > 0 && !inConst && !visit(i, end)) return;
            i = end;
            continue;
        }
        ++i;
    }
}

}  // namespace

LiftedText LiftLiterals(const std::string& text) {
    LiftedText out;
    size_t copied = 0;
    ForEachLiftable(text, [&](size_t begin, size_t end) {
        std::string digits = text.substr(begin, end - begin);
        if (!digits.empty() && (digits.back() == 'f' || digits.back() == 'F')) digits.pop_back();
        float value = 0.0f;
        const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        if (ec != std::errc() || ptr != digits.data() + digits.size()) return true;   // not ours: left in place
        out.text.append(text, copied, begin - copied);
        out.text += "u_lit[" + std::to_string(out.values.size()) + "]";
        out.values.push_back(value);
        copied = end;
        return out.values.size() < kMaxLifted;
    });
    out.text.append(text, copied, std::string::npos);
    return out;
}

bool FindFirstLiftable(const std::string& text, size_t* begin, size_t* end) {
    bool found = false;
    ForEachLiftable(text, [&](size_t b, size_t e) {
        *begin = b;
        *end = e;
        found = true;
        return false;
    });
    return found;
}

}  // namespace sdfvj
