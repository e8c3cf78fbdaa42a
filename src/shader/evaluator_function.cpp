// The evaluator's translation of functions: blocks and branches, calls inlined, variables, loads,
// stores and access chains (evaluator_translator.h).
#include <glslang/SPIRV/spirv.hpp>

#include "shader/evaluator_translator.h"

namespace sdfvj::eval {

namespace {
std::string NameOr(const std::unordered_map<uint32_t, std::string>& names, uint32_t id) {
    auto it = names.find(id);
    return it == names.end() ? "%" + std::to_string(id) : it->second;
}
}  // namespace

Value Translator::Val(Ctx& ctx, uint32_t id) {
    auto c = constants.find(id);
    if (c != constants.end()) return c->second;
    auto v = ctx.values.find(id);
    if (v == ctx.values.end()) Fail("a value used before its definition (%" + std::to_string(id) + ")");
    return v->second;
}

Pointer Translator::Ptr(Ctx& ctx, uint32_t id) {
    auto p = ctx.ptrs.find(id);
    if (p != ctx.ptrs.end()) return p->second;
    auto g = globals.find(id);
    if (g == globals.end()) Fail("a pointer the translator cannot follow (%" + std::to_string(id) + ")");
    Pointer ptr;
    const Type& pt = Ty(g->second.type);
    ptr.type = pt.elem;
    const std::string name = NameOr(names, id);
    const uint32_t pointee = Ty(pt.elem).op;
    switch (g->second.storage) {
    case spv::StorageClassPrivate: ptr.group = g->second.group; return ptr;
    case spv::StorageClassUniformConstant:
        if (pointee == spv::OpTypeImage || pointee == spv::OpTypeSampledImage || pointee == spv::OpTypeSampler) {
            ptr.kind = Pointer::kOther;
            ptr.what = "a texture or sampler ('" + name + "')";
            return ptr;
        }
        for (size_t k = 0; k < uniformSlots.size(); ++k)
            if (uniformSlots[k] == name) {
                ptr.kind = Pointer::kUniform;
                ptr.slot = (uint32_t)k;
                return ptr;
            }
        ptr.kind = Pointer::kOther;
        ptr.what = "the uniform '" + name + "' (not in the evaluator's uniform slots)";
        return ptr;
    case spv::StorageClassWorkgroup: ptr.kind = Pointer::kOther; ptr.what = "shared memory ('" + name + "')"; return ptr;
    case spv::StorageClassInput: case spv::StorageClassOutput:
        ptr.kind = Pointer::kOther;
        ptr.what = "the shader input or output '" + name + "'";
        return ptr;
    default: ptr.kind = Pointer::kOther; ptr.what = "the buffer or block '" + name + "'"; return ptr;
    }
}

Value Translator::Load(const Pointer& p, uint32_t type) {
    if (p.kind == Pointer::kOther) Fail(p.what);
    const uint32_t regs = std::max(Ty(type).regs, 1u);
    if (p.kind == Pointer::kUniform) {
        if (regs != 1 || p.dynamic) Fail("a uniform matrix, array or struct");
        Value v = Fresh(1);
        Emit(kLoadUniform, Reg(v, 0), {}, {}, {}, p.slot);
        return p.lane >= 0 ? Broadcast(v, (uint32_t)p.lane) : v;
    }
    if (p.dynamic) {
        Value v = Fresh(regs);
        for (uint32_t r = 0; r < regs; ++r) {
            Emit(kLoadIndexed, Reg(v, r), Reg(p.index, 0), {}, {}, 0, r == 0);
            code.back().immReg = At(p.group, p.off + r);
        }
        return p.lane >= 0 ? Broadcast(v, (uint32_t)p.lane) : v;
    }
    Value src{false, p.group, p.off, regs};
    auto k = known.find(p.group);
    if (k != known.end()) {
        src = k->second;
        src.off += p.off;
        src.size = regs;
        if (p.lane < 0) return src;   // a value: immutable, unlike the variable
    }
    if (p.lane >= 0) return Broadcast(src, (uint32_t)p.lane);
    Value v = Fresh(regs);
    Copy(v.base, 0, src, true);
    return v;
}

void Translator::Store(const Pointer& p, const Value& v) {
    if (p.kind == Pointer::kOther) Fail(p.what);
    if (p.kind == Pointer::kUniform) Fail("a store to a uniform");
    known.erase(p.group);
    if (p.dynamic) {
        if (p.lane >= 0) Fail("a vector component store at a run-time array index");
        for (uint32_t r = 0; r < v.size; ++r) {
            Emit(kStoreIndexed, {}, Reg(p.index, 0), Reg(v, r), {}, 0, false);
            code.back().immReg = At(p.group, p.off + r);
        }
        return;
    }
    if (p.lane >= 0) {
        Emit(kSetComp, At(p.group, p.off), Reg(v, 0), {}, {}, (uint32_t)p.lane, false);
        return;
    }
    const bool whole = p.off == 0 && v.size == groups[p.group].size;
    Copy(p.group, p.off, v, whole);
    if (whole) known[p.group] = v;
}

Pointer Translator::AccessChain(Ctx& ctx, const Raw& r) {
    const uint32_t* o = r.w + 1;
    Pointer p = Ptr(ctx, o[2]);
    uint32_t cur = p.type;
    for (uint32_t k = 3; k + 1 < r.n; ++k) {
        const uint32_t id = o[k];
        const Type& t = Ty(cur);
        const bool isConst = constInts.count(id) != 0;
        if (t.op == spv::OpTypeStruct) {
            const uint32_t m = IntConstant(id);
            if (m >= t.members.size()) Fail("a struct member out of range");
            p.off += t.offsets[m];
            cur = t.members[m];
        } else if (t.op == spv::OpTypeArray || t.op == spv::OpTypeMatrix) {
            const uint32_t elemRegs = t.op == spv::OpTypeArray ? Ty(t.elem).regs : 1;
            if (p.kind == Pointer::kUniform) Fail("an indexed uniform");
            if (isConst) {
                const int64_t i = constInts[id];
                if (i < 0 || (uint64_t)i >= t.count) Fail("a constant array index out of range");
                p.off += (uint32_t)i * elemRegs;
            } else {
                Value index = Val(ctx, id);
                if (elemRegs != 1) {
                    Value scaled = Fresh(1);
                    Emit(kMul, Reg(scaled, 0), Reg(index, 0), K((float)elemRegs));
                    index = scaled;
                }
                if (p.dynamic) {
                    Value sum = Fresh(1);
                    Emit(kAdd, Reg(sum, 0), Reg(p.index, 0), Reg(index, 0));
                    index = sum;
                }
                p.dynamic = true;
                p.index = index;
            }
            cur = t.elem;
        } else if (t.op == spv::OpTypeVector) {
            if (!isConst) Fail("a vector component at a run-time index");
            p.lane = (int)IntConstant(id);
            cur = t.elem;
        } else {
            Fail("an access chain into a " + std::to_string(t.op) + " type");
        }
    }
    p.type = cur;
    return p;
}

void Translator::EmitCall(Ctx& ctx, const Raw& r, std::vector<uint32_t>& stack) {
    const uint32_t* o = r.w + 1;
    auto f = functions.find(o[2]);
    if (f == functions.end()) Fail("a call of a function without a body");
    const Function& fn = f->second;
    Ctx callee;
    callee.cont = Label();
    const uint32_t regs = Ty(o[0]).op == spv::OpTypeVoid ? 0 : std::max(Ty(o[0]).regs, 1u);
    if (regs) callee.retGroup = NewGroup(regs);
    for (size_t k = 0; k < fn.params.size(); ++k) {
        const uint32_t arg = o[3 + k];
        if (Ty(fn.params[k].second).op == spv::OpTypePointer)
            callee.ptrs[fn.params[k].first] = Ptr(ctx, arg);
        else
            callee.values[fn.params[k].first] = Val(ctx, arg);
    }
    EmitFunction(fn, callee, stack);
    labelPc[callee.cont] = (uint32_t)code.size();
    known.clear();   // the callee's returns jump here
    if (regs) ctx.values[o[1]] = Value{false, callee.retGroup, 0, regs};
}

void Translator::EmitReturn(Ctx& ctx, const Value* v, bool last) {
    if (v && ctx.retGroup != kNone) Copy(ctx.retGroup, 0, *v, true);
    if (ctx.hook) {
        Emit(kReturn, {}, {}, {}, {}, 0, false);
        code.back().returnGroup = ctx.retGroup;
    } else if (!last) {
        Jump(kJump, {}, ctx.cont);
    }
}

void Translator::EmitFunction(const Function& fn, Ctx& ctx, std::vector<uint32_t>& stack) {
    for (uint32_t id : stack)
        if (id == fn.id) Fail("recursion ('" + NameOr(names, fn.id) + "')");
    stack.push_back(fn.id);
    // Blocks, their labels, and each phi's moves at the end of its predecessors.
    std::vector<std::pair<uint32_t, size_t>> blocks;   // label id, first instruction
    for (size_t k = 0; k < fn.body.size(); ++k) {
        const Raw& r = fn.body[k];
        const uint32_t op = r.w[0] & 0xffff;
        if (op == spv::OpLabel) {
            blocks.push_back({r.w[1], k + 1});
            ctx.labels[r.w[1]] = Label();
        } else if (op == spv::OpPhi) {
            ctx.values[r.w[2]] = Fresh(std::max(Ty(r.w[1]).regs, 1u));
            for (uint32_t j = 3; j + 1 < r.n; j += 2) ctx.phis[r.w[j + 1]].push_back({r.w[2], r.w[j]});
        }
    }
    for (size_t b = 0; b < blocks.size(); ++b) {
        const uint32_t block = blocks[b].first;
        const uint32_t next = b + 1 < blocks.size() ? blocks[b + 1].first : 0;
        const bool last = b + 1 == blocks.size();
        labelPc[ctx.labels[block]] = (uint32_t)code.size();
        if (b > 0) known.clear();   // a jump may enter here (never the entry block: SPIR-V forbids it)
        auto phiMoves = [&] {
            auto it = ctx.phis.find(block);
            if (it == ctx.phis.end()) return;
            for (auto [phi, value] : it->second) {
                const Value dst = ctx.values[phi];
                Copy(dst.base, 0, Val(ctx, value), true);
            }
        };
        auto jumpTo = [&](uint32_t target) {
            if (target != next) Jump(kJump, {}, ctx.labels.at(target));
        };
        for (size_t k = blocks[b].second; k < fn.body.size(); ++k) {
            const Raw& r = fn.body[k];
            const uint32_t op = r.w[0] & 0xffff;
            const uint32_t* o = r.w + 1;
            if (op == spv::OpLabel) break;
            switch (op) {
            case spv::OpLine: line = o[1]; break;
            case spv::OpNoLine: case spv::OpNop: case spv::OpSelectionMerge: case spv::OpLoopMerge: case spv::OpPhi:
                break;
            case spv::OpVariable: {
                Pointer p;
                p.type = Ty(o[0]).elem;
                p.group = NewGroup(Ty(p.type).regs);
                ctx.ptrs[o[1]] = p;
                if (r.n > 4) Copy(p.group, 0, Val(ctx, o[3]), true);
                break;
            }
            case spv::OpUndef: {
                const uint32_t regs = std::max(Ty(o[0]).regs, 1u);
                const uint32_t base = (uint32_t)program.constants.size();
                for (uint32_t i = 0; i < regs; ++i) program.constants.push_back({0, 0, 0, 0});
                ctx.values[o[1]] = Value{true, base, 0, regs};
                break;
            }
            case spv::OpLoad: ctx.values[o[1]] = Load(Ptr(ctx, o[2]), o[0]); break;
            case spv::OpStore: Store(Ptr(ctx, o[0]), Val(ctx, o[1])); break;
            case spv::OpCopyMemory: {
                const Pointer src = Ptr(ctx, o[1]);
                Store(Ptr(ctx, o[0]), Load(src, src.type));
                break;
            }
            case spv::OpAccessChain: case spv::OpInBoundsAccessChain: ctx.ptrs[o[1]] = AccessChain(ctx, r); break;
            case spv::OpFunctionCall: EmitCall(ctx, r, stack); break;
            case spv::OpBranch:
                phiMoves();
                jumpTo(o[0]);
                break;
            case spv::OpBranchConditional: {
                phiMoves();
                const Opnd cond = Reg(Val(ctx, o[0]), 0);
                if (o[1] == next) {
                    Jump(kJumpIfZero, cond, ctx.labels.at(o[2]));
                } else if (o[2] == next) {
                    Jump(kJumpIfNotZero, cond, ctx.labels.at(o[1]));
                } else {
                    Jump(kJumpIfZero, cond, ctx.labels.at(o[2]));
                    Jump(kJump, {}, ctx.labels.at(o[1]));
                }
                break;
            }
            case spv::OpSwitch: {
                phiMoves();
                const Value sel = Val(ctx, o[0]);
                for (uint32_t j = 2; j + 1 < r.n - 1; j += 2) {
                    Value eq = Fresh(1);
                    Emit(kEqual, Reg(eq, 0), Reg(sel, 0), K((float)(int32_t)o[j]));
                    Jump(kJumpIfNotZero, Reg(eq, 0), ctx.labels.at(o[j + 1]));
                }
                jumpTo(o[1]);
                break;
            }
            case spv::OpReturn: case spv::OpUnreachable: EmitReturn(ctx, nullptr, last); break;
            case spv::OpReturnValue: {
                const Value v = Val(ctx, o[0]);
                EmitReturn(ctx, &v, last);
                break;
            }
            case spv::OpKill: Fail("discard");
            default:
                if (!EmitOp(ctx, r)) Fail(OpName(op));
            }
        }
    }
    stack.pop_back();
}

}  // namespace sdfvj::eval
