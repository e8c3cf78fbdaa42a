// Structure-aware JSON for the scene and preset fuzzers: the fuzz bytes are decoded into
// choices (FuzzedDataProvider) that build a mostly valid document, where each field is kept,
// dropped, given a wrong type, a huge/negative/non-finite-looking number, deep nesting or junk.
// libFuzzer mutates the choices, so it explores the checks behind a valid skeleton instead of
// stopping at the first syntax error. Used by fuzz_scene.cpp and fuzz_preset.cpp only.
#pragma once
#include <fuzzer/FuzzedDataProvider.h>

#include <cstdio>
#include <iterator>
#include <string>
#include <vector>

namespace sdfvj::fuzz {

class JsonGen {
public:
    explicit JsonGen(FuzzedDataProvider& in) : in_(in) {}

    // Any JSON value, at most `depth` levels (the depth check lives in the code under test).
    std::string AnyValue(int depth) {
        switch (in_.ConsumeIntegralInRange<int>(0, 9)) {
            case 0: return "null";
            case 1: return in_.ConsumeBool() ? "true" : "false";
            case 2: return Number();
            case 3: return String();
            case 4: return Nest(in_.ConsumeIntegralInRange<int>(1, 200));
            case 5: {
                if (depth <= 0) return "[]";
                std::string s = "[";
                for (int i = 0, n = in_.ConsumeIntegralInRange<int>(0, 4); i < n; ++i) s += (i ? "," : "") + AnyValue(depth - 1);
                return s + "]";
            }
            case 6: {
                if (depth <= 0) return "{}";
                std::string s = "{";
                for (int i = 0, n = in_.ConsumeIntegralInRange<int>(0, 4); i < n; ++i)
                    s += (i ? "," : "") + String() + ":" + AnyValue(depth - 1);
                return s + "}";
            }
            case 7: return Junk();
            default: return Number();
        }
    }

    // A number as JSON text: the awkward ones (overflow float, overflow double, huge integers,
    // denormals, negative zero) or a random one.
    std::string Number() {
        static const char* kAwkward[] = {"0", "-0", "-0.0", "1", "-1", "0.5", "1e300", "-1e300", "1e39", "-1e39",
                                         "3.4028235e38", "3.4028236e38", "1e400", "-1e400", "1e-320", "4.9e-324",
                                         "99999999999999999999999", "-99999999999999999999999",
                                         "18446744073709551615", "18446744073709551616", "9223372036854775807",
                                         "-9223372036854775808", "-9223372036854775809", "1e9", "1000000001",
                                         "180", "179.9999", "1e-7", "8", "9", "2147483648", "0e0", "1E+2"};
        if (in_.ConsumeBool()) return kAwkward[in_.ConsumeIntegralInRange<size_t>(0, std::size(kAwkward) - 1)];
        if (in_.ConsumeBool()) return std::to_string(in_.ConsumeIntegral<int64_t>());
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.9g", in_.ConsumeFloatingPoint<double>());
        std::string s = buf;
        return (s.find("inf") != std::string::npos || s.find("nan") != std::string::npos) ? "1e999" : s;
    }

    // A quoted string: usually printable, sometimes escapes, control bytes or invalid UTF-8.
    std::string String() {
        std::string raw = in_.ConsumeRandomLengthString(48);
        std::string s = "\"";
        const bool rawBytes = in_.ConsumeIntegralInRange<int>(0, 7) == 0;
        for (char c : raw) {
            if (rawBytes) s += c;
            else if (c == '"' || c == '\\') s += std::string("\\") + c;
            else if ((unsigned char)c < 0x20) s += "\\u001f";
            else s += c;
        }
        return s + "\"";
    }

    std::string Nest(int depth) {
        const bool object = in_.ConsumeBool();
        std::string s;
        for (int i = 0; i < depth; ++i) s += object ? "{\"k\":" : "[";
        if (in_.ConsumeBool()) {  // balanced, or left open
            s += "1";
            for (int i = 0; i < depth; ++i) s += object ? "}" : "]";
        }
        return s;
    }

    std::string Junk() { return in_.ConsumeRandomLengthString(16); }

    // A field's value: the valid one most of the time, else a hostile one. Choice 0 (what an
    // exhausted provider returns) is always the valid skeleton, here and below.
    std::string Field(const std::string& valid) {
        switch (in_.ConsumeIntegralInRange<int>(0, 7)) {
            case 5: return AnyValue(3);
            case 6: return Number();
            case 7: return String();
            default: return valid;
        }
    }

    // `"KEY": value` unless the field is dropped; the key's case is sometimes changed.
    void Member(std::vector<std::string>* members, std::string key, const std::string& value) {
        const int roll = in_.ConsumeIntegralInRange<int>(0, 15);
        if (roll == 13) return;                                          // missing
        if (roll == 14 && !key.empty()) key[0] = char(key[0] ^ 0x20);    // case typo
        members->push_back("\"" + key + "\": " + value);
        if (roll == 15) members->push_back(String() + ": " + AnyValue(2));  // an unknown key too
    }

    static std::string Object(const std::vector<std::string>& members) {
        std::string s = "{";
        for (size_t i = 0; i < members.size(); ++i) s += (i ? ",\n  " : "\n  ") + members[i];
        return s + "\n}";
    }

    // Last touches on the whole text: truncate it, or splice junk in, now and then.
    std::string Damage(std::string text) {
        switch (in_.ConsumeIntegralInRange<int>(0, 15)) {
            case 14: return text.substr(0, in_.ConsumeIntegralInRange<size_t>(0, text.size()));
            case 15: return text.insert(in_.ConsumeIntegralInRange<size_t>(0, text.size()), Junk());
            default: return text;
        }
    }

    FuzzedDataProvider& in() { return in_; }

private:
    FuzzedDataProvider& in_;
};

}  // namespace sdfvj::fuzz
