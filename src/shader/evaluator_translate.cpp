// SPIR-V (glslang's, unoptimized) -> the evaluator's code (evaluator.h). Every hook is translated
// with its callees inlined (GLSL has no recursion); SSA values and variables become virtual
// register groups, which evaluator_regalloc.cpp maps to registers. Ops are translated one by one
// in evaluator_ops.cpp; this file holds the module, the functions, memory and control flow.
#define SPV_ENABLE_UTILITY_CODE
#include <glslang/SPIRV/spirv.hpp>

#include <cstring>

#include <cstdlib>

#include "shader/evaluator_translator.h"

namespace sdfvj::eval {

std::string Translator::OpName(uint32_t op) {
    switch (op) {
    case spv::OpImageSampleImplicitLod: case spv::OpImageSampleExplicitLod: case spv::OpImageFetch:
    case spv::OpImageRead: case spv::OpSampledImage: case spv::OpImageQuerySize: case spv::OpImageQuerySizeLod:
        return "a texture or image access";
    case spv::OpDPdx: case spv::OpDPdy: case spv::OpFwidth: return "a derivative (dFdx, dFdy, fwidth)";
    case spv::OpOuterProduct: return "outerProduct";
    case spv::OpVectorInsertDynamic: return "a vector component written at a run-time index";
    case spv::OpControlBarrier: case spv::OpMemoryBarrier: return "a barrier";
    default: return "SPIR-V op " + std::to_string(op);
    }
}

void Translator::Fail(const std::string& what) { throw Unsupported{what}; }

uint32_t Translator::NewGroup(uint32_t size) {
    groups.push_back(Group{std::max(size, 1u), -1, -1});
    return (uint32_t)groups.size() - 1;
}

uint32_t Translator::Const(std::array<float, 4> v) {
    uint32_t key[4];
    std::memcpy(key, v.data(), sizeof key);
    const std::string k(reinterpret_cast<const char*>(key), sizeof key);
    auto it = constIndex.find(k);
    if (it != constIndex.end()) return it->second;
    program.constants.push_back(v);
    const uint32_t i = (uint32_t)program.constants.size() - 1;
    constIndex[k] = i;
    return i;
}

Opnd Translator::Reg(const Value& v, uint32_t r) const {
    Opnd o;
    if (v.isConst) {
        o.isConst = true;
        o.off = v.base + v.off + r;
    } else {
        o.group = v.base;
        o.off = v.off + r;
    }
    return o;
}

Opnd Translator::At(uint32_t group, uint32_t off) {
    Opnd o;
    o.group = group;
    o.off = off;
    return o;
}

void Translator::Emit(uint32_t op, Opnd dst, Opnd a, Opnd b, Opnd c, uint32_t imm, bool kill) {
    VInstr in;
    in.op = op;
    in.dst = dst;
    in.a = a;
    in.b = b;
    in.c = c;
    in.imm = imm;
    in.kill = kill;
    code.push_back(in);
}

Value Translator::Fresh(uint32_t size) { return Value{false, NewGroup(size), 0, size}; }

void Translator::Copy(uint32_t group, uint32_t off, const Value& src, bool whole) {
    for (uint32_t r = 0; r < src.size; ++r) Emit(kMov, At(group, off + r), Reg(src, r), {}, {}, 0, whole && r == 0);
}

Value Translator::Broadcast(const Value& scalar, uint32_t lane) {
    if (scalar.isConst) {   // scalar constants are stored in every lane
        const auto& k = program.constants[scalar.base + scalar.off];
        if (k[0] == k[1] && k[0] == k[2] && k[0] == k[3]) return scalar;
    }
    Value v = Fresh(1);
    Emit(kSwizzle, Reg(v, 0), Reg(scalar, 0), {}, {}, lane * 0x249u, true);   // lane in all four selectors
    return v;
}

uint32_t Translator::Label() {
    labelPc.push_back(kNone);
    return (uint32_t)labelPc.size() - 1;
}

void Translator::Jump(uint32_t op, Opnd cond, uint32_t label) {
    Emit(op, {}, cond, {}, {}, 0, false);
    code.back().label = label;
}

// ---- the module ----

void Translator::ParseModule(const std::vector<uint32_t>& w) {
    if (w.size() < 5 || w[0] != spv::MagicNumber) Fail("a module that is not SPIR-V");
    Function* fn = nullptr;
    for (size_t at = 5; at < w.size();) {
        const uint32_t op = w[at] & 0xffff, count = w[at] >> 16;
        if (count == 0 || at + count > w.size()) Fail("a truncated SPIR-V module");
        Raw raw{&w[at], count};
        const uint32_t* o = raw.w + 1;
        bool hasResult = false, hasType = false;
        spv::HasResultAndType((spv::Op)op, &hasResult, &hasType);
        if (hasResult && hasType && count > 2) idType[o[1]] = o[0];
        switch (op) {
        case spv::OpName: names[o[0]] = reinterpret_cast<const char*>(o + 1); break;
        case spv::OpExtInstImport:
            if (std::strcmp(reinterpret_cast<const char*>(o + 1), "GLSL.std.450") == 0) glslStd = o[0];
            break;
        case spv::OpTypeVoid: case spv::OpTypeBool: case spv::OpTypeInt: case spv::OpTypeFloat:
        case spv::OpTypeVector: case spv::OpTypeMatrix: case spv::OpTypeArray: case spv::OpTypeStruct:
        case spv::OpTypePointer: case spv::OpTypeFunction: case spv::OpTypeImage: case spv::OpTypeSampler:
        case spv::OpTypeSampledImage: case spv::OpTypeRuntimeArray:
            ParseType(op, raw);
            break;
        case spv::OpConstant: case spv::OpSpecConstant: case spv::OpConstantTrue: case spv::OpConstantFalse:
        case spv::OpSpecConstantTrue: case spv::OpSpecConstantFalse: case spv::OpConstantComposite:
        case spv::OpSpecConstantComposite: case spv::OpConstantNull: case spv::OpUndef:
            if (fn) {
                fn->body.push_back(raw);   // OpUndef inside a function: handled there
                break;
            }
            ParseConstant(op, raw);
            break;
        case spv::OpVariable:
            if (fn) {
                fn->body.push_back(raw);
                break;
            }
            globals[o[1]] = Global{o[0], o[2], count > 4 ? o[3] : 0};
            break;
        case spv::OpFunction:
            fn = &functions[o[1]];
            fn->id = o[1];
            fn->resultType = o[0];
            break;
        case spv::OpFunctionParameter:
            if (fn) fn->params.push_back({o[1], o[0]});
            break;
        case spv::OpFunctionEnd: fn = nullptr; break;
        default:
            if (fn) fn->body.push_back(raw);
            else if (op == spv::OpSpecConstantOp) Fail("a specialization constant expression");
            break;
        }
        at += count;
    }
}

void Translator::ParseType(uint32_t op, const Raw& raw) {
    const uint32_t* o = raw.w + 1;
    Type& t = types[o[0]];
    t.op = op;
    switch (op) {
    case spv::OpTypeBool: case spv::OpTypeFloat: t.regs = 1; break;
    case spv::OpTypeInt: t.regs = 1; t.isSigned = o[2] != 0; break;
    case spv::OpTypeVector: t.regs = 1; t.elem = o[1]; t.count = o[2]; t.lanes = o[2]; break;
    case spv::OpTypeMatrix: t.elem = o[1]; t.count = o[2]; t.regs = o[2]; break;
    case spv::OpTypeArray:
        t.elem = o[1];
        t.count = IntConstant(o[2]);
        t.regs = t.count * types[o[1]].regs;
        break;
    case spv::OpTypeStruct:
        for (uint32_t k = 1; k + 1 < raw.n; ++k) {
            t.members.push_back(o[k]);
            t.offsets.push_back(t.regs);
            t.regs += types[o[k]].regs;
        }
        break;
    case spv::OpTypePointer: t.storage = o[1]; t.elem = o[2]; break;
    default: break;   // void, functions, images: no registers
    }
}

uint32_t Translator::IntConstant(uint32_t id) {
    auto it = constInts.find(id);
    if (it == constInts.end()) Fail("an index that is not a constant integer");
    return (uint32_t)it->second;
}

std::array<float, 4> Translator::ConstLanes(const Value& v) const { return program.constants[v.base + v.off]; }

void Translator::ParseConstant(uint32_t op, const Raw& raw) {
    const uint32_t* o = raw.w + 1;
    const uint32_t type = o[0], id = o[1];
    const Type& t = Ty(type);
    auto splat = [&](float f) { return Value{true, Const({f, f, f, f}), 0, 1}; };
    switch (op) {
    case spv::OpConstantTrue: case spv::OpSpecConstantTrue: constants[id] = splat(1); break;
    case spv::OpConstantFalse: case spv::OpSpecConstantFalse: constants[id] = splat(0); break;
    case spv::OpConstant: case spv::OpSpecConstant: {
        float f;
        if (t.op == spv::OpTypeFloat) {
            std::memcpy(&f, &o[2], 4);
        } else {
            const int64_t i = t.isSigned ? (int64_t)(int32_t)o[2] : (int64_t)o[2];
            constInts[id] = i;
            f = (float)i;
        }
        constants[id] = splat(f);
        break;
    }
    case spv::OpConstantNull: case spv::OpUndef: {
        const uint32_t base = (uint32_t)program.constants.size();
        for (uint32_t r = 0; r < std::max(t.regs, 1u); ++r) program.constants.push_back({0, 0, 0, 0});
        constants[id] = Value{true, base, 0, std::max(t.regs, 1u)};
        break;
    }
    default: {   // composites
        if (t.op == spv::OpTypeVector) {
            std::array<float, 4> lanes{0, 0, 0, 0};
            for (uint32_t k = 0; k < t.count && k < 4 && 3 + k < raw.n; ++k) lanes[k] = ConstLanes(ConstOf(o[2 + k]))[0];
            constants[id] = Value{true, Const(lanes), 0, 1};
        } else {   // matrices, arrays, structs: their members' registers one after another
            const uint32_t base = (uint32_t)program.constants.size();
            for (uint32_t k = 2; k < raw.n - 1; ++k) {
                const Value m = ConstOf(o[k]);
                for (uint32_t r = 0; r < m.size; ++r) program.constants.push_back(program.constants[m.base + m.off + r]);
            }
            constants[id] = Value{true, base, 0, t.regs};
        }
        break;
    }
    }
}

Value Translator::ConstOf(uint32_t id) {
    auto it = constants.find(id);
    if (it == constants.end()) Fail("a composite constant of a non-constant part");
    return it->second;
}

const Type& Translator::Ty(uint32_t id) const {
    auto it = types.find(id);
    static const Type kNoType;
    return it == types.end() ? kNoType : it->second;
}

// ---- entries ----

bool Translator::Run(const std::vector<uint32_t>& words, const std::vector<std::string>& slots, std::string* error) {
    try {
        uniformSlots = slots;
        ParseModule(words);
        if (program.constants.size() >= kConstFlag) Fail("more than 32767 constants");
        // SCENE_STATE globals: the first registers, in declaration order.
        uint32_t next = 0;
        for (auto& [id, g] : globals) {
            const Type& pt = Ty(g.type);
            if (g.storage == spv::StorageClassPrivate) {
                const uint32_t size = Ty(pt.elem).regs;
                g.group = NewGroup(size);
                groups[g.group].fixed = (int)next;
                next += std::max(size, 1u);
            }
        }
        if (next > kMaxRegisters / 2) Fail("more than " + std::to_string(kMaxRegisters / 2) + " registers of globals");
        globalRegs = next;
        CheckMainInitializers();
        std::vector<std::pair<uint32_t, uint32_t>> pins;
        for (const std::string& hook : HookNames()) {
            const Function* fn = FindFunction(hook);
            if (!fn) continue;
            Entry e;
            e.name = hook;
            e.pc = (uint32_t)code.size();
            Ctx ctx;
            ctx.hook = true;
            std::vector<uint32_t> argGroups;
            for (auto [param, type] : fn->params) {
                const Type& pt = Ty(type);
                if (pt.op != spv::OpTypePointer) Fail("a hook argument passed by value");
                const uint32_t g = NewGroup(Ty(pt.elem).regs);
                Pointer ptr;
                ptr.group = g;
                ptr.type = pt.elem;
                ctx.ptrs[param] = ptr;
                argGroups.push_back(g);
                pins.push_back({g, e.pc});
            }
            if (Ty(fn->resultType).op != spv::OpTypeVoid) ctx.retGroup = NewGroup(Ty(fn->resultType).regs);
            // Globals with constant initializers: set where the state starts (sceneSetup, or every
            // hook of a scene without one).
            if (hook == "sceneSetup" || !FindFunction("sceneSetup"))
                for (auto& [id, g] : globals)
                    if (g.group != kNone && g.init) Copy(g.group, 0, ConstOf(g.init), true);
            std::vector<uint32_t> stack;
            EmitFunction(*fn, ctx, stack);
            entryArgs.push_back(argGroups);
            entryResult.push_back(ctx.retGroup);
            program.entries.push_back(e);
        }
        if (program.entries.empty()) Fail("a unit without any scene hook (map, sceneBound, ...)");
        std::vector<uint32_t*> pcs;
        for (Entry& e : program.entries) pcs.push_back(&e.pc);
        for (auto& pin : pins) pcs.push_back(&pin.second);
        // SDFVJ_EVAL_COPIES=0 keeps the copies (for measuring what their removal gains).
        static const bool removeCopies = [] {
            const char* v = std::getenv("SDFVJ_EVAL_COPIES");
            return !(v && std::string(v) == "0");
        }();
        for (int pass = 0; pass < 2; ++pass) {   // a second pass finds the copies the first one's removals exposed
            if (removeCopies) PropagateCopies(code, groups, labelPc, pcs);
            RemoveDeadCode(code, groups, labelPc, pcs);
        }
        if (!AllocateRegisters(code, groups, pins, labelPc, globalRegs, &program, error)) {
            *error = "evaluator: " + files.name + ": " + *error;
            return false;
        }
        for (size_t k = 0; k < program.entries.size(); ++k) {
            auto reg = [&](uint32_t g) {
                return (uint32_t)(groups[g].fixed >= 0 ? groups[g].fixed : std::max(groups[g].reg, (int)globalRegs));
            };
            for (uint32_t g : entryArgs[k]) program.entries[k].args.push_back(reg(g));
            if (entryResult[k] != kNone) program.entries[k].result = reg(entryResult[k]);
        }
        program.uniforms = uniformSlots;
        return true;
    } catch (const Unsupported& u) {
        *error = "evaluator: " + (line ? files.Where(line) : files.name) + ": " + u.what + " is not supported";
        return false;
    }
}

const Function* Translator::FindFunction(const std::string& name) const {
    for (const auto& [id, fn] : functions) {
        auto it = names.find(id);
        if (it == names.end()) continue;
        const std::string& n = it->second;
        if (n == name || n.rfind(name + "(", 0) == 0) return &fn;
    }
    return nullptr;
}

// main() computes a global's non-constant initializer (`float g = sin(u_time);`); the hooks alone
// would never see it.
void Translator::CheckMainInitializers() {
    const Function* main = FindFunction("main");
    if (!main) return;
    for (const Raw& r : main->body) {
        if ((r.w[0] & 0xffff) != spv::OpStore) continue;
        auto it = globals.find(r.w[1]);
        if (it != globals.end() && it->second.storage == spv::StorageClassPrivate) {
            auto n = names.find(r.w[1]);
            Fail("the global '" + (n == names.end() ? std::string("?") : n->second) +
                 "' with an initializer computed at run time");
        }
    }
}

bool TranslateSpirv(const std::vector<uint32_t>& words, const std::vector<std::string>& uniformSlots,
                    const UnitFiles& files, Program* out, std::string* error) {
    Translator t(files);
    if (!t.Run(words, uniformSlots, error)) return false;
    *out = std::move(t.program);
    return true;
}

}  // namespace sdfvj::eval
