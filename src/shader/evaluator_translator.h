// The SPIR-V translator's state (evaluator_translate.cpp, evaluator_function.cpp, evaluator_ops.cpp).
#pragma once
#include <map>
#include <unordered_map>

#include "shader/evaluator_internal.h"

namespace sdfvj::eval {

struct Unsupported {
    std::string what;   // "a texture lookup": the message adds " is not supported"
};

struct Raw {
    const uint32_t* w;   // w[0]: word count << 16 | opcode; operands from w[1]
    uint32_t n;
};

struct Type {
    uint32_t op = 0;              // spv::OpTypeFloat, ...
    uint32_t regs = 0;            // registers a value of it takes (scalars and vectors 1)
    uint32_t lanes = 1;           // vector size (1 for scalars)
    uint32_t elem = 0;            // vector: component; matrix: column; array: element; pointer: pointee
    uint32_t count = 0;           // vector size, matrix columns, array length
    bool isSigned = false;
    uint32_t storage = 0;         // pointers
    std::vector<uint32_t> members, offsets;   // structs: member types and their first registers
};

// A value: `size` registers from `off` of a group, or of the constants from index base.
struct Value {
    bool isConst = false;
    uint32_t base = kNone;
    uint32_t off = 0;
    uint32_t size = 1;
};

// Where a load or store goes: a variable's registers (with a constant lane, or a run-time index
// already scaled to registers), or a uniform.
struct Pointer {
    enum Kind { kVar, kUniform, kOther } kind = kVar;
    uint32_t group = kNone;
    uint32_t off = 0;
    int lane = -1;
    bool dynamic = false;
    Value index;                  // registers past off, when dynamic
    uint32_t slot = 0;            // kUniform
    std::string what;             // kOther: what it is, for the message
    uint32_t type = 0;            // the pointee's type
};

struct Global {
    uint32_t type = 0;            // pointer type
    uint32_t storage = 0;
    uint32_t init = 0;
    uint32_t group = kNone;       // Private: a fixed group
};

struct Function {
    uint32_t id = 0, resultType = 0;
    std::vector<std::pair<uint32_t, uint32_t>> params;   // id, type
    std::vector<Raw> body;
};

// One inlined call of a function.
struct Ctx {
    bool hook = false;                                   // the hook itself: a return is kReturn
    std::unordered_map<uint32_t, Value> values;
    std::unordered_map<uint32_t, Pointer> ptrs;
    std::unordered_map<uint32_t, uint32_t> labels;       // block id -> label
    std::unordered_map<uint32_t, std::vector<std::pair<uint32_t, uint32_t>>> phis;   // pred -> (phi, value)
    uint32_t retGroup = kNone;
    uint32_t cont = kNone;                               // the label after the call
};

class Translator {
public:
    explicit Translator(const UnitFiles& f) : files(f) {}
    bool Run(const std::vector<uint32_t>& words, const std::vector<std::string>& slots, std::string* error);
    Program program;

private:
    friend struct OpEmitter;
    const UnitFiles& files;
    std::vector<std::string> uniformSlots;
    std::unordered_map<uint32_t, std::string> names;
    std::unordered_map<uint32_t, Type> types;
    std::unordered_map<uint32_t, Value> constants;
    std::unordered_map<uint32_t, uint32_t> idType;   // every result id's type
    std::unordered_map<uint32_t, int64_t> constInts;
    std::map<uint32_t, Global> globals;
    std::map<uint32_t, Function> functions;
    std::unordered_map<std::string, uint32_t> constIndex;
    uint32_t glslStd = kNone;
    uint32_t globalRegs = 0;
    uint32_t line = 0;
    std::vector<VInstr> code;
    // Within a block, the value a variable group was last stored whole from: a load reads that
    // value instead of copying the variable (forgotten at every block a jump may enter).
    std::unordered_map<uint32_t, Value> known;
    std::vector<Group> groups;
    std::vector<uint32_t> labelPc;
    std::vector<std::vector<uint32_t>> entryArgs;
    std::vector<uint32_t> entryResult;

    [[noreturn]] static void Fail(const std::string& what);
    static std::string OpName(uint32_t op);
    void ParseModule(const std::vector<uint32_t>& w);
    void ParseType(uint32_t op, const Raw& raw);
    void ParseConstant(uint32_t op, const Raw& raw);
    uint32_t IntConstant(uint32_t id);
    Value ConstOf(uint32_t id);
    std::array<float, 4> ConstLanes(const Value& v) const;
    const Type& Ty(uint32_t id) const;
    const Function* FindFunction(const std::string& name) const;
    void CheckMainInitializers();

    uint32_t NewGroup(uint32_t size);
    uint32_t Const(std::array<float, 4> v);
    uint32_t ConstScalar(float f) { return Const({f, f, f, f}); }
    Opnd K(float f) { Opnd o; o.isConst = true; o.off = ConstScalar(f); return o; }
    Opnd Reg(const Value& v, uint32_t r) const;
    static Opnd At(uint32_t group, uint32_t off);
    void Emit(uint32_t op, Opnd dst, Opnd a, Opnd b = {}, Opnd c = {}, uint32_t imm = 0, bool kill = true);
    Value Fresh(uint32_t size);
    void Copy(uint32_t group, uint32_t off, const Value& src, bool whole);
    Value Broadcast(const Value& scalar, uint32_t lane = 0);
    uint32_t Label();
    void Jump(uint32_t op, Opnd cond, uint32_t label);

    // evaluator_function.cpp
    void EmitFunction(const Function& fn, Ctx& ctx, std::vector<uint32_t>& stack);
    Value Val(Ctx& ctx, uint32_t id);
    Pointer Ptr(Ctx& ctx, uint32_t id);
    Value Load(const Pointer& p, uint32_t type);
    void Store(const Pointer& p, const Value& v);
    Pointer AccessChain(Ctx& ctx, const Raw& r);
    void EmitCall(Ctx& ctx, const Raw& r, std::vector<uint32_t>& stack);
    void EmitReturn(Ctx& ctx, const Value* v, bool last);
    // evaluator_ops.cpp: the rest (arithmetic, composites, matrices, GLSL.std.450); false: unknown op
    bool EmitOp(Ctx& ctx, const Raw& r);
    bool EmitExt(Ctx& ctx, const Raw& r);
    Value Construct(const std::vector<std::pair<Opnd, uint32_t>>& lanes);
    uint32_t Lanes(uint32_t id) const;        // the vector size of a value's type (1: a scalar)
    bool IsFloatType(uint32_t type) const;
    void Walk(uint32_t type, const uint32_t* idx, uint32_t n, uint32_t* off, int* lane, uint32_t* resultType) const;
    Value Extract(const Value& v, uint32_t type, const uint32_t* idx, uint32_t n, uint32_t* resultType);
};

}  // namespace sdfvj::eval
