// The evaluator's translation of SPIR-V's value ops: arithmetic, comparisons, conversions,
// composites, matrices and GLSL.std.450 (evaluator_translator.h). Scalars live in .x; where a
// scalar meets a vector (vector * scalar, a select on a scalar bool) it is broadcast first.
#include <glslang/SPIRV/GLSL.std.450.h>
#include <glslang/SPIRV/spirv.hpp>

#include <cmath>
#include <limits>

#include "shader/evaluator_translator.h"

namespace sdfvj::eval {

uint32_t Translator::Lanes(uint32_t id) const {
    auto it = idType.find(id);
    return it == idType.end() ? 1 : std::max(Ty(it->second).lanes, 1u);
}

bool Translator::IsFloatType(uint32_t type) const {
    const Type& t = Ty(type);
    return (t.op == spv::OpTypeVector ? Ty(t.elem).op : t.op) == spv::OpTypeFloat;
}

Value Translator::Construct(const std::vector<std::pair<Opnd, uint32_t>>& lanes) {
    Value v = Fresh(1);
    auto same = [](const Opnd& x, const Opnd& y) { return x.isConst == y.isConst && x.group == y.group && x.off == y.off; };
    std::vector<Opnd> sources;
    for (const auto& l : lanes) {
        bool seen = false;
        for (const Opnd& s : sources) seen = seen || same(s, l.first);
        if (!seen) sources.push_back(l.first);
    }
    // The first swizzle takes two sources; each further one keeps what is there and adds one.
    for (size_t s = 0; s < sources.size(); s += (s == 0 ? 2 : 1)) {
        const bool first = s == 0;
        uint32_t imm = 0;
        for (uint32_t i = 0; i < lanes.size() && i < 4; ++i) {
            uint32_t sel = first ? 0 : i;
            if (first && same(lanes[i].first, sources[0])) sel = lanes[i].second;
            const size_t b = first ? 1 : s;
            if (b < sources.size() && same(lanes[i].first, sources[b])) sel = 4 + lanes[i].second;
            imm |= sel << (3 * i);
        }
        const Opnd b = first ? (sources.size() > 1 ? sources[1] : Opnd{}) : sources[s];
        Emit(kSwizzle, Reg(v, 0), first ? sources[0] : Reg(v, 0), b, {}, imm, first);
    }
    return v;
}

// The path of constant indices into a composite: its register offset and, into a vector, its lane.
void Translator::Walk(uint32_t type, const uint32_t* idx, uint32_t n, uint32_t* off, int* lane,
                      uint32_t* resultType) const {
    *off = 0;
    *lane = -1;
    uint32_t cur = type;
    for (uint32_t k = 0; k < n; ++k) {
        const Type& t = Ty(cur);
        if (t.op == spv::OpTypeStruct) {
            *off += t.offsets.at(idx[k]);
            cur = t.members.at(idx[k]);
        } else if (t.op == spv::OpTypeMatrix) {
            *off += idx[k];
            cur = t.elem;
        } else if (t.op == spv::OpTypeArray) {
            *off += idx[k] * Ty(t.elem).regs;
            cur = t.elem;
        } else {   // a vector
            *lane = (int)idx[k];
            cur = t.elem;
        }
    }
    *resultType = cur;
}

Value Translator::Extract(const Value& v, uint32_t type, const uint32_t* idx, uint32_t n, uint32_t* resultType) {
    uint32_t off;
    int lane;
    Walk(type, idx, n, &off, &lane, resultType);
    const Value at{v.isConst, v.base, v.off + off, std::max(Ty(*resultType).regs, 1u)};
    if (lane < 0) return at;
    if (v.isConst) {
        const float f = program.constants[at.base + at.off][lane & 3];
        return Value{true, ConstScalar(f), 0, 1};
    }
    return Broadcast(at, (uint32_t)lane);
}

bool Translator::EmitOp(Ctx& ctx, const Raw& r) {
    const uint32_t op = r.w[0] & 0xffff;
    const uint32_t* o = r.w + 1;
    const uint32_t type = o[0], id = o[1];
    const Type& t = Ty(type);
    const uint32_t regs = std::max(t.regs, 1u);
    auto arg = [&](uint32_t k) { return Val(ctx, o[2 + k]); };
    auto lanewise = [&](uint32_t mop, uint32_t nargs, uint32_t imm = 0) {
        Value a = arg(0), b = nargs > 1 ? arg(1) : Value{}, c = nargs > 2 ? arg(2) : Value{};
        Value v = Fresh(regs);
        for (uint32_t k = 0; k < regs; ++k)
            Emit(mop, Reg(v, k), Reg(a, k), nargs > 1 ? Reg(b, k) : Opnd{}, nargs > 2 ? Reg(c, k) : Opnd{}, imm);
        ctx.values[id] = v;
    };
    auto negated = [&](uint32_t mop) {   // unordered comparisons: NaN compares true
        Value a = arg(0), b = arg(1), v = Fresh(1);
        Emit(mop, Reg(v, 0), Reg(a, 0), Reg(b, 0));
        Emit(kNot, Reg(v, 0), Reg(v, 0), {}, {}, 0, false);
        ctx.values[id] = v;
    };
    switch (op) {
    case spv::OpFNegate: case spv::OpSNegate: lanewise(kNeg, 1); return true;
    case spv::OpFAdd: case spv::OpIAdd: lanewise(kAdd, 2); return true;
    case spv::OpFSub: case spv::OpISub: lanewise(kSub, 2); return true;
    case spv::OpFMul: case spv::OpIMul: lanewise(kMul, 2); return true;
    case spv::OpFDiv: lanewise(kDiv, 2); return true;
    case spv::OpSDiv: case spv::OpUDiv: lanewise(kIntDiv, 2); return true;
    case spv::OpFMod: case spv::OpSMod: case spv::OpUMod: lanewise(kMod, 2); return true;
    case spv::OpFRem: case spv::OpSRem: lanewise(kIntRem, 2); return true;
    case spv::OpFOrdLessThan: case spv::OpSLessThan: case spv::OpULessThan: lanewise(kLess, 2); return true;
    case spv::OpFOrdLessThanEqual: case spv::OpSLessThanEqual: case spv::OpULessThanEqual: lanewise(kLessEqual, 2); return true;
    case spv::OpFOrdGreaterThan: case spv::OpSGreaterThan: case spv::OpUGreaterThan: lanewise(kGreater, 2); return true;
    case spv::OpFOrdGreaterThanEqual: case spv::OpSGreaterThanEqual: case spv::OpUGreaterThanEqual:
        lanewise(kGreaterEqual, 2);
        return true;
    case spv::OpFUnordLessThan: negated(kGreaterEqual); return true;
    case spv::OpFUnordLessThanEqual: negated(kGreater); return true;
    case spv::OpFUnordGreaterThan: negated(kLessEqual); return true;
    case spv::OpFUnordGreaterThanEqual: negated(kLess); return true;
    case spv::OpFOrdEqual: case spv::OpFUnordEqual: case spv::OpIEqual: case spv::OpLogicalEqual: lanewise(kEqual, 2); return true;
    case spv::OpFOrdNotEqual: case spv::OpFUnordNotEqual: case spv::OpINotEqual: case spv::OpLogicalNotEqual:
        lanewise(kNotEqual, 2);
        return true;
    case spv::OpLogicalAnd: lanewise(kAnd, 2); return true;
    case spv::OpLogicalOr: lanewise(kOr, 2); return true;
    case spv::OpLogicalNot: lanewise(kNot, 1); return true;
    case spv::OpShiftRightLogical: case spv::OpShiftRightArithmetic: lanewise(kShiftRight, 2); return true;
    case spv::OpShiftLeftLogical: lanewise(kShiftLeft, 2); return true;
    case spv::OpBitwiseAnd: lanewise(kBitAnd, 2); return true;
    case spv::OpBitwiseOr: lanewise(kBitOr, 2); return true;
    case spv::OpBitwiseXor: lanewise(kBitXor, 2); return true;
    case spv::OpNot: {
        const Type& e = t.op == spv::OpTypeVector ? Ty(t.elem) : t;
        if (!e.isSigned) Fail("the bitwise not (~) of an unsigned integer");
        Value a = arg(0), v = Fresh(1);
        Emit(kSub, Reg(v, 0), K(-1.0f), Reg(a, 0));   // ~x = -x - 1 for a signed integer
        ctx.values[id] = v;
        return true;
    }
    case spv::OpAny: lanewise(kAny, 1, Lanes(o[2])); return true;
    case spv::OpAll: lanewise(kAll, 1, Lanes(o[2])); return true;
    case spv::OpDot: lanewise(kDot, 2, Lanes(o[2])); return true;
    case spv::OpConvertFToS: case spv::OpConvertFToU: lanewise(kTrunc, 1); return true;
    case spv::OpConvertSToF: case spv::OpConvertUToF: case spv::OpUConvert: case spv::OpSConvert:
    case spv::OpFConvert: case spv::OpCopyObject:
        ctx.values[id] = arg(0);   // the same value: ints are floats here
        return true;
    case spv::OpBitcast: {
        auto it = idType.find(o[2]);
        if (IsFloatType(type) || (it != idType.end() && IsFloatType(it->second)))
            Fail("a bit cast between floats and integers (floatBitsToInt, intBitsToFloat, ...)");
        ctx.values[id] = arg(0);
        return true;
    }
    case spv::OpIsNan: {
        Value a = arg(0), v = Fresh(1);
        Emit(kNotEqual, Reg(v, 0), Reg(a, 0), Reg(a, 0));
        ctx.values[id] = v;
        return true;
    }
    case spv::OpIsInf: {
        Value a = arg(0), v = Fresh(1);
        Emit(kAbs, Reg(v, 0), Reg(a, 0));
        Emit(kEqual, Reg(v, 0), Reg(v, 0), K(std::numeric_limits<float>::infinity()), {}, 0, false);
        ctx.values[id] = v;
        return true;
    }
    case spv::OpSelect: {
        Value cond = arg(0), a = arg(1), b = arg(2);
        if (Lanes(o[2]) == 1 && (t.lanes > 1 || regs > 1)) cond = Broadcast(cond);
        Value v = Fresh(regs);
        for (uint32_t k = 0; k < regs; ++k) Emit(kSelect, Reg(v, k), Reg(a, k), Reg(b, k), Reg(cond, 0));
        ctx.values[id] = v;
        return true;
    }
    case spv::OpVectorTimesScalar: case spv::OpMatrixTimesScalar: {
        Value a = arg(0), s = Broadcast(arg(1)), v = Fresh(regs);
        for (uint32_t k = 0; k < regs; ++k) Emit(kMul, Reg(v, k), Reg(a, k), Reg(s, 0));
        ctx.values[id] = v;
        return true;
    }
    case spv::OpMatrixTimesVector: case spv::OpMatrixTimesMatrix: {
        // Column k of the result: sum over j of M[j] * B[k][j].
        Value m = arg(0), b = arg(1), v = Fresh(regs);
        const uint32_t inner = Ty(idType.at(o[2])).count;
        for (uint32_t k = 0; k < regs; ++k)
            for (uint32_t j = 0; j < inner; ++j) {
                const Value bj = Broadcast(Value{b.isConst, b.base, b.off + k, 1}, j);
                if (j == 0) Emit(kMul, Reg(v, k), Reg(m, j), Reg(bj, 0));
                else Emit(kFma, Reg(v, k), Reg(m, j), Reg(bj, 0), Reg(v, k), 0, false);
            }
        ctx.values[id] = v;
        return true;
    }
    case spv::OpVectorTimesMatrix: {
        Value a = arg(0), m = arg(1);
        std::vector<std::pair<Opnd, uint32_t>> lanes;
        for (uint32_t j = 0; j < Ty(idType.at(o[3])).count; ++j) {
            Value d = Fresh(1);
            Emit(kDot, Reg(d, 0), Reg(a, 0), Reg(m, j), {}, Lanes(o[2]));
            lanes.push_back({Reg(d, 0), 0});
        }
        ctx.values[id] = Construct(lanes);
        return true;
    }
    case spv::OpTranspose: {
        Value m = arg(0), v = Fresh(regs);
        const uint32_t cols = Ty(idType.at(o[2])).count;
        for (uint32_t i = 0; i < regs; ++i) {
            std::vector<std::pair<Opnd, uint32_t>> lanes;
            for (uint32_t j = 0; j < cols; ++j) lanes.push_back({Reg(m, j), i});
            Copy(v.base, i, Construct(lanes), i == 0);
        }
        ctx.values[id] = v;
        return true;
    }
    case spv::OpCompositeConstruct: {
        if (t.op == spv::OpTypeVector) {
            std::vector<std::pair<Opnd, uint32_t>> lanes;
            for (uint32_t k = 2; k + 1 < r.n; ++k) {
                const Value c = Val(ctx, o[k]);
                for (uint32_t l = 0; l < Lanes(o[k]); ++l) lanes.push_back({Reg(c, 0), l});
            }
            ctx.values[id] = Construct(lanes);
        } else {
            Value v = Fresh(regs);
            uint32_t off = 0;
            for (uint32_t k = 2; k + 1 < r.n; ++k) {
                const Value c = Val(ctx, o[k]);
                Copy(v.base, off, c, off == 0);
                off += c.size;
            }
            ctx.values[id] = v;
        }
        return true;
    }
    case spv::OpCompositeExtract: {
        uint32_t rt;
        ctx.values[id] = Extract(arg(0), idType.at(o[2]), o + 3, r.n - 4, &rt);
        return true;
    }
    case spv::OpCompositeInsert: {
        Value obj = arg(0), comp = arg(1), v = Fresh(regs);
        Copy(v.base, 0, comp, true);
        uint32_t off, rt;
        int lane;
        Walk(type, o + 4, r.n - 5, &off, &lane, &rt);
        if (lane >= 0) Emit(kSetComp, At(v.base, off), Reg(obj, 0), {}, {}, (uint32_t)lane, false);
        else Copy(v.base, off, obj, false);
        ctx.values[id] = v;
        return true;
    }
    case spv::OpVectorShuffle: {
        Value a = arg(0), b = arg(1), v = Fresh(1);
        const uint32_t n1 = Lanes(o[2]);
        uint32_t imm = 0;
        for (uint32_t i = 0; i + 5 < r.n && i < 4; ++i) {
            const uint32_t c = o[4 + i];
            const uint32_t sel = c == 0xffffffffu ? 0 : c < n1 ? c : 4 + (c - n1);
            imm |= sel << (3 * i);
        }
        Emit(kSwizzle, Reg(v, 0), Reg(a, 0), Reg(b, 0), {}, imm);
        ctx.values[id] = v;
        return true;
    }
    case spv::OpVectorExtractDynamic: {   // a chain of selects over the lanes
        Value a = arg(0), index = arg(1), v = Broadcast(a, 0);
        for (uint32_t l = 1; l < Lanes(o[2]); ++l) {
            Value eq = Fresh(1), bl = Broadcast(a, l);
            Emit(kEqual, Reg(eq, 0), Reg(index, 0), K((float)l));
            Emit(kSelect, Reg(v, 0), Reg(bl, 0), Reg(v, 0), Reg(eq, 0), 0, false);
        }
        ctx.values[id] = v;
        return true;
    }
    case spv::OpExtInst: return EmitExt(ctx, r);
    default: return false;
    }
}

bool Translator::EmitExt(Ctx& ctx, const Raw& r) {
    const uint32_t* o = r.w + 1;
    const uint32_t type = o[0], id = o[1];
    if (o[2] != glslStd) Fail("an extended instruction set other than GLSL.std.450");
    const uint32_t inst = o[3];
    auto arg = [&](uint32_t k) { return Val(ctx, o[4 + k]); };
    const uint32_t regs = std::max(Ty(type).regs, 1u);
    auto lanewise = [&](uint32_t mop, uint32_t nargs) {
        Value a = arg(0), b = nargs > 1 ? arg(1) : Value{}, c = nargs > 2 ? arg(2) : Value{};
        Value v = Fresh(regs);
        for (uint32_t k = 0; k < regs; ++k)
            Emit(mop, Reg(v, k), Reg(a, k), nargs > 1 ? Reg(b, k) : Opnd{}, nargs > 2 ? Reg(c, k) : Opnd{});
        ctx.values[id] = v;
    };
    auto length = [&](const Value& x, uint32_t lanes) {
        Value v = Fresh(1);
        if (lanes == 1) {
            Emit(kAbs, Reg(v, 0), Reg(x, 0));
        } else {
            Emit(kDot, Reg(v, 0), Reg(x, 0), Reg(x, 0), {}, lanes);
            Emit(kSqrt, Reg(v, 0), Reg(v, 0), {}, {}, 0, false);
        }
        return v;
    };
    const float kPi = 3.14159265358979323846f;
    switch (inst) {
    case GLSLstd450Round: case GLSLstd450RoundEven: lanewise(kRound, 1); return true;
    case GLSLstd450Trunc: lanewise(kTrunc, 1); return true;
    case GLSLstd450FAbs: case GLSLstd450SAbs: lanewise(kAbs, 1); return true;
    case GLSLstd450FSign: case GLSLstd450SSign: lanewise(kSign, 1); return true;
    case GLSLstd450Floor: lanewise(kFloor, 1); return true;
    case GLSLstd450Ceil: lanewise(kCeil, 1); return true;
    case GLSLstd450Fract: lanewise(kFract, 1); return true;
    case GLSLstd450Sin: lanewise(kSin, 1); return true;
    case GLSLstd450Cos: lanewise(kCos, 1); return true;
    case GLSLstd450Tan: lanewise(kTan, 1); return true;
    case GLSLstd450Asin: lanewise(kAsin, 1); return true;
    case GLSLstd450Acos: lanewise(kAcos, 1); return true;
    case GLSLstd450Atan: lanewise(kAtan, 1); return true;
    case GLSLstd450Atan2: lanewise(kAtan2, 2); return true;
    case GLSLstd450Pow: lanewise(kPow, 2); return true;
    case GLSLstd450Exp: lanewise(kExp, 1); return true;
    case GLSLstd450Log: lanewise(kLog, 1); return true;
    case GLSLstd450Exp2: lanewise(kExp2, 1); return true;
    case GLSLstd450Log2: lanewise(kLog2, 1); return true;
    case GLSLstd450Sqrt: lanewise(kSqrt, 1); return true;
    case GLSLstd450InverseSqrt: lanewise(kInverseSqrt, 1); return true;
    case GLSLstd450FMin: case GLSLstd450UMin: case GLSLstd450SMin: case GLSLstd450NMin: lanewise(kMin, 2); return true;
    case GLSLstd450FMax: case GLSLstd450UMax: case GLSLstd450SMax: case GLSLstd450NMax: lanewise(kMax, 2); return true;
    case GLSLstd450FClamp: case GLSLstd450UClamp: case GLSLstd450SClamp: case GLSLstd450NClamp:
        lanewise(kClamp, 3);
        return true;
    case GLSLstd450FMix: lanewise(kMix, 3); return true;
    case GLSLstd450Step: lanewise(kStep, 2); return true;
    case GLSLstd450SmoothStep: lanewise(kSmoothstep, 3); return true;
    case GLSLstd450Fma: lanewise(kFma, 3); return true;
    case GLSLstd450Cross: lanewise(kCross, 2); return true;
    case GLSLstd450Radians: case GLSLstd450Degrees: {
        Value a = arg(0), v = Fresh(1);
        Emit(kMul, Reg(v, 0), Reg(a, 0), K(inst == GLSLstd450Radians ? kPi / 180.0f : 180.0f / kPi));
        ctx.values[id] = v;
        return true;
    }
    case GLSLstd450Length: ctx.values[id] = length(arg(0), Lanes(o[4])); return true;
    case GLSLstd450Distance: {
        Value a = arg(0), b = arg(1), d = Fresh(1);
        Emit(kSub, Reg(d, 0), Reg(a, 0), Reg(b, 0));
        ctx.values[id] = length(d, Lanes(o[4]));
        return true;
    }
    case GLSLstd450Normalize: {
        Value a = arg(0), v = Fresh(1);
        if (Lanes(o[4]) == 1) {
            Emit(kSign, Reg(v, 0), Reg(a, 0));
        } else {
            Value d = Fresh(1);
            Emit(kDot, Reg(d, 0), Reg(a, 0), Reg(a, 0), {}, Lanes(o[4]));   // in every lane
            Emit(kInverseSqrt, Reg(d, 0), Reg(d, 0), {}, {}, 0, false);
            Emit(kMul, Reg(v, 0), Reg(a, 0), Reg(d, 0));
        }
        ctx.values[id] = v;
        return true;
    }
    case GLSLstd450Reflect: {   // I - 2 dot(N, I) N
        Value i = arg(0), n = arg(1), d = Fresh(1), v = Fresh(1);
        Emit(kDot, Reg(d, 0), Reg(n, 0), Reg(i, 0), {}, Lanes(o[4]));
        Emit(kMul, Reg(d, 0), Reg(d, 0), Reg(n, 0), {}, 0, false);
        Emit(kAdd, Reg(d, 0), Reg(d, 0), Reg(d, 0), {}, 0, false);
        Emit(kSub, Reg(v, 0), Reg(i, 0), Reg(d, 0));
        ctx.values[id] = v;
        return true;
    }
    case GLSLstd450FaceForward: {   // dot(Nref, I) < 0 ? N : -N
        Value n = arg(0), i = arg(1), nref = arg(2), d = Fresh(1), neg = Fresh(1), v = Fresh(1);
        Emit(kDot, Reg(d, 0), Reg(nref, 0), Reg(i, 0), {}, Lanes(o[4]));
        Emit(kLess, Reg(d, 0), Reg(d, 0), K(0.0f), {}, 0, false);
        Emit(kNeg, Reg(neg, 0), Reg(n, 0));
        Emit(kSelect, Reg(v, 0), Reg(n, 0), Reg(neg, 0), Reg(d, 0));
        ctx.values[id] = v;
        return true;
    }
    default: Fail("the GLSL.std.450 function #" + std::to_string(inst));
    }
}

}  // namespace sdfvj::eval
