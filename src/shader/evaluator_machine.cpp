// The evaluator's machine on the CPU (evaluator.h Run): the same register machine as
// render/eval.glsl, float32 math, each op as evaluator.h's enum says. Tests use it to check the
// translation against the C++ build of a scene.
#include <cmath>
#include <cstdint>

#include "shader/evaluator.h"

namespace sdfvj::eval {

namespace {

using V4 = std::array<float, 4>;

float Sign(float x) { return x > 0.0f ? 1.0f : x < 0.0f ? -1.0f : 0.0f; }
float Smooth(float e0, float e1, float x) {
    float t = (x - e0) / (e1 - e0);
    t = t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
    return t * t * (3.0f - 2.0f * t);
}
int64_t I(float x) { return (int64_t)x; }

}  // namespace

bool Run(const Program& program, const std::string& name, const std::vector<std::array<float, 4>>& args, Machine* m,
         std::array<float, 4>* result, std::string* error) {
    const Entry* e = program.Find(name);
    if (!e) {
        *error = "evaluator: no entry '" + name + "'";
        return false;
    }
    if (args.size() != e->args.size()) {
        *error = "evaluator: '" + name + "' takes " + std::to_string(e->args.size()) + " arguments";
        return false;
    }
    auto& R = m->R;
    if (R.size() < kMaxRegisters) R.resize(kMaxRegisters, {0, 0, 0, 0});
    for (size_t k = 0; k < args.size(); ++k) R[e->args[k]] = args[k];
    const V4 zero{0, 0, 0, 0};
    auto read = [&](uint32_t o) -> V4 {
        if (o == kNone) return zero;
        if (o & kConstFlag) return program.constants[o & 0x7fffu];
        const V4& r = R[o & (kMaxRegisters - 1)];
        const uint32_t lane = (o >> kLaneShift) & 7u;
        if (lane == 0) return r;
        const float v = r[(lane - 1) & 3u];
        return {v, v, v, v};
    };
    const size_t n = program.code.size();
    uint64_t budget = 50'000'000;   // a loop that never ends fails the test, not the process
    for (uint32_t pc = e->pc; pc < n;) {
        if (--budget == 0) {
            *error = "evaluator: '" + name + "' ran past 50M instructions";
            return false;
        }
        const Instr& in = program.code[pc++];
        const V4 A = read(in.a), B = read(in.b), C = read(in.c);
        V4 d = in.dst != kNone && in.dst < kMaxRegisters ? R[in.dst] : zero;
        auto lanes = [&](auto f) {
            for (int i = 0; i < 4; ++i) d[i] = f(A[i], B[i], C[i]);
        };
        auto flag = [](bool b) { return b ? 1.0f : 0.0f; };
        switch (in.op) {
        case kNop: continue;
        case kMov: d = A; break;
        case kSwizzle:
            for (int i = 0; i < 4; ++i) {
                const uint32_t sel = (in.imm >> (3 * i)) & 7u;
                d[i] = (sel < 4 ? A : B)[sel & 3];
            }
            break;
        case kSetComp: d[in.imm & 3] = A[0]; break;
        case kLoadUniform:
            d = in.imm < m->uniformValues.size() ? m->uniformValues[in.imm] : zero;
            break;
        case kLoadIndexed: {
            const int64_t at = (int64_t)in.imm + I(A[0]);
            d = at >= 0 && at < (int64_t)kMaxRegisters ? R[at] : zero;
            break;
        }
        case kStoreIndexed: {
            const int64_t at = (int64_t)in.imm + I(A[0]);
            if (at >= 0 && at < (int64_t)kMaxRegisters) R[at] = B;
            continue;
        }
        case kAdd: lanes([](float a, float b, float) { return a + b; }); break;
        case kSub: lanes([](float a, float b, float) { return a - b; }); break;
        case kMul: lanes([](float a, float b, float) { return a * b; }); break;
        case kDiv: lanes([](float a, float b, float) { return a / b; }); break;
        case kNeg: lanes([](float a, float, float) { return -a; }); break;
        case kFma: lanes([](float a, float b, float c) { return a * b + c; }); break;
        case kMod: lanes([](float a, float b, float) { return a - b * std::floor(a / b); }); break;
        case kMin: lanes([](float a, float b, float) { return std::fmin(a, b); }); break;
        case kMax: lanes([](float a, float b, float) { return std::fmax(a, b); }); break;
        case kClamp: lanes([](float a, float b, float c) { return std::fmin(std::fmax(a, b), c); }); break;
        case kMix: lanes([](float a, float b, float c) { return a + (b - a) * c; }); break;
        case kStep: lanes([](float a, float b, float) { return b < a ? 0.0f : 1.0f; }); break;
        case kSmoothstep: lanes([](float a, float b, float c) { return Smooth(a, b, c); }); break;
        case kAbs: lanes([](float a, float, float) { return std::fabs(a); }); break;
        case kSign: lanes([](float a, float, float) { return Sign(a); }); break;
        case kFloor: lanes([](float a, float, float) { return std::floor(a); }); break;
        case kCeil: lanes([](float a, float, float) { return std::ceil(a); }); break;
        case kFract: lanes([](float a, float, float) { return a - std::floor(a); }); break;
        case kRound: lanes([](float a, float, float) { return std::round(a); }); break;
        case kTrunc: lanes([](float a, float, float) { return std::trunc(a); }); break;
        case kSqrt: lanes([](float a, float, float) { return std::sqrt(a); }); break;
        case kInverseSqrt: lanes([](float a, float, float) { return 1.0f / std::sqrt(a); }); break;
        case kExp: lanes([](float a, float, float) { return std::exp(a); }); break;
        case kExp2: lanes([](float a, float, float) { return std::exp2(a); }); break;
        case kLog: lanes([](float a, float, float) { return std::log(a); }); break;
        case kLog2: lanes([](float a, float, float) { return std::log2(a); }); break;
        case kPow: lanes([](float a, float b, float) { return std::pow(a, b); }); break;
        case kSin: lanes([](float a, float, float) { return std::sin(a); }); break;
        case kCos: lanes([](float a, float, float) { return std::cos(a); }); break;
        case kTan: lanes([](float a, float, float) { return std::tan(a); }); break;
        case kAsin: lanes([](float a, float, float) { return std::asin(a); }); break;
        case kAcos: lanes([](float a, float, float) { return std::acos(a); }); break;
        case kAtan: lanes([](float a, float, float) { return std::atan(a); }); break;
        case kAtan2: lanes([](float a, float b, float) { return std::atan2(a, b); }); break;
        case kDot: {
            float s = 0.0f;
            for (uint32_t i = 0; i < in.imm && i < 4; ++i) s += A[i] * B[i];
            d = {s, s, s, s};
            break;
        }
        case kCross:
            d[0] = A[1] * B[2] - A[2] * B[1];
            d[1] = A[2] * B[0] - A[0] * B[2];
            d[2] = A[0] * B[1] - A[1] * B[0];
            break;
        case kLess: lanes([&](float a, float b, float) { return flag(a < b); }); break;
        case kLessEqual: lanes([&](float a, float b, float) { return flag(a <= b); }); break;
        case kGreater: lanes([&](float a, float b, float) { return flag(a > b); }); break;
        case kGreaterEqual: lanes([&](float a, float b, float) { return flag(a >= b); }); break;
        case kEqual: lanes([&](float a, float b, float) { return flag(a == b); }); break;
        case kNotEqual: lanes([&](float a, float b, float) { return flag(a != b); }); break;
        case kAnd: lanes([&](float a, float b, float) { return flag(a != 0.0f && b != 0.0f); }); break;
        case kOr: lanes([&](float a, float b, float) { return flag(a != 0.0f || b != 0.0f); }); break;
        case kNot: lanes([&](float a, float, float) { return flag(a == 0.0f); }); break;
        case kSelect: lanes([](float a, float b, float c) { return c != 0.0f ? a : b; }); break;
        case kIntDiv: lanes([](float a, float b, float) { return std::trunc(a / b); }); break;
        case kIntRem: lanes([](float a, float b, float) { return a - b * std::trunc(a / b); }); break;
        case kShiftRight: lanes([](float a, float b, float) { return std::floor(a / std::exp2(b)); }); break;
        case kShiftLeft: lanes([](float a, float b, float) { return a * std::exp2(b); }); break;
        case kBitAnd: lanes([](float a, float b, float) { return (float)(I(a) & I(b)); }); break;
        case kBitOr: lanes([](float a, float b, float) { return (float)(I(a) | I(b)); }); break;
        case kBitXor: lanes([](float a, float b, float) { return (float)(I(a) ^ I(b)); }); break;
        case kAny: case kAll: {
            bool any = false, all = true;
            for (uint32_t i = 0; i < in.imm && i < 4; ++i) {
                any = any || A[i] != 0.0f;
                all = all && A[i] != 0.0f;
            }
            const float v = flag(in.op == kAny ? any : all);
            d = {v, v, v, v};
            break;
        }
        case kJump: pc = in.imm; continue;
        case kJumpIfZero: if (A[0] == 0.0f) pc = in.imm; continue;
        case kJumpIfNotZero: if (A[0] != 0.0f) pc = in.imm; continue;
        case kReturn:
            if (result) *result = e->result == kNone ? zero : R[e->result];
            return true;
        default:
            *error = "evaluator: unknown op " + std::to_string(in.op) + " at " + std::to_string(pc - 1);
            return false;
        }
        if (in.dst >= kMaxRegisters) {
            *error = "evaluator: op " + std::to_string(in.op) + " at " + std::to_string(pc - 1) + " writes no register";
            return false;
        }
        R[in.dst] = d;
    }
    *error = "evaluator: '" + name + "' ran off the end of the code";
    return false;
}

}  // namespace sdfvj::eval
