// The scene evaluator (issue 12): a scene's hook functions (map, mapGround, mapObjects, sceneBound,
// ...) translated on the CPU, with no driver compile, into code for a small register machine. One
// program per scene *shape* (the scene's text outside its hook functions' bodies, render/eval.glsl)
// runs that code on the GPU, so a save that only changes what the hooks compute goes on screen with
// no build: the new code is uploaded and drawn in the save's first reload step, while the optimized
// program builds behind it.
//
// Front end: glslang (Debian's glslang-dev) turns the scene's GLSL into SPIR-V (its preprocessor,
// types, overloads and constant folding are GLSL's own); Translate() turns the SPIR-V of the hooks
// into the machine's code: functions inlined, registers allocated by liveness.
//
// The machine (the same in GLSL, shaders/render/eval.glsl, and in C++, Run() below):
// - Registers R[0..kMaxRegisters) are vec4 of float. A scalar lives in .x. Ints and uints are
//   floats holding the integer value (exact below 2^24); bools are 1.0 / 0.0.
// - Constants K[] are vec4 too. An operand is 16 bits: bit 15 set reads K[operand & 0x7fff], else
//   a register: R[operand & (kMaxRegisters - 1)], or with a lane in bits 12-14 (kLaneShift; 1-4:
//   x, y, z, w) that lane of it in all four (what a kSwizzle broadcasting one lane made, folded
//   into its readers). kNone (0xffff): no operand.
// - An instruction is a uvec4: x = op, y = dst | a << 16, z = b | c << 16, w = imm (a swizzle, a
//   component, a jump target or a uniform slot, as the op says).
// - Registers [0, globals) persist between calls of one invocation (a scene's SCENE_STATE globals,
//   written by sceneSetup, read by map); every other register is scratch.
// - A call: the caller writes the entry's argument registers, runs from entry.pc to RET, and reads
//   the result from entry.result (a vec3 result in .xyz, a float in .x).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "shader/shader.h"

namespace sdfvj::eval {

constexpr uint32_t kMaxRegisters = 128;  // the GLSL machine's register array; Translate() fails past it
constexpr uint32_t kConstFlag = 0x8000u;
constexpr uint32_t kNone = 0xffffu;
constexpr uint32_t kLaneShift = 12;      // a register operand's lane: (operand >> kLaneShift) & 7, 0: the whole vec4

// Component-wise over the 4 lanes unless said otherwise. A, B, C are the operands' values.
enum Op : uint32_t {
    kNop = 0,
    kMov,        // dst = A
    kSwizzle,    // dst[i] = (sel < 4 ? A : B)[sel & 3], sel = (imm >> 3*i) & 7 for i = 0..3
    kSetComp,    // dst[imm] = A.x (the other lanes of dst kept)
    kLoadUniform,// dst = the uniform in slot imm (Program::uniforms), a float/int in .x, vecN in .xyz(w)
    kLoadIndexed,// dst = R[imm + int(A.x)]   (arrays indexed at run time; imm = the array's first register)
    kStoreIndexed,// R[imm + int(A.x)] = B
    kAdd, kSub, kMul, kDiv, kNeg,
    kFma,        // A * B + C
    kMod,        // A - B * floor(A / B)  (GLSL mod)
    kMin, kMax, kClamp /* clamp(A, B, C) */, kMix /* mix(A, B, C) */,
    kStep /* step(A, B) */, kSmoothstep /* smoothstep(A, B, C) */,
    kAbs, kSign, kFloor, kCeil, kFract, kRound, kTrunc,
    kSqrt, kInverseSqrt, kExp, kExp2, kLog, kLog2, kPow,
    kSin, kCos, kTan, kAsin, kAcos, kAtan, kAtan2 /* atan(A, B) */,
    kDot,        // dst.x = dot of A and B over the first imm lanes (2, 3 or 4); dst.yzw = dst.x
    kCross,      // dst.xyz = cross(A.xyz, B.xyz)
    kLess, kLessEqual, kGreater, kGreaterEqual, kEqual, kNotEqual,   // 1.0 or 0.0 per lane
    kAnd, kOr, kNot,                   // logical, on 1.0 / 0.0
    kSelect,     // dst = C != 0 ? A : B, per lane
    kIntDiv,     // trunc(A / B)  (GLSL int division)
    kIntRem,     // A - B * trunc(A / B)
    kShiftRight, // floor(A / 2^B)  (arithmetic shift of an integer value)
    kShiftLeft,  // A * 2^B
    kBitAnd, kBitOr, kBitXor,         // on the integer values (non-negative, below 2^24)
    kAny, kAll,  // dst.x = any / all of the first imm lanes of A non-zero
    kJump,       // pc = imm
    kJumpIfZero, // if A.x == 0: pc = imm
    kJumpIfNotZero,
    kReturn,     // the call ends
    kOpCount
};

struct Instr {
    uint32_t op = kNop;
    uint32_t dst = kNone, a = kNone, b = kNone, c = kNone;
    uint32_t imm = 0;
    std::array<uint32_t, 4> Packed() const {
        return {op, (dst & 0xffffu) | (a << 16), (b & 0xffffu) | (c << 16), imm};
    }
};

// A hook the translation found in the scene.
struct Entry {
    std::string name;                 // "map", "sceneBound", ...
    uint32_t pc = 0;                  // first instruction
    std::vector<uint32_t> args;       // each argument's register (vec3 p: one register, .xyz)
    uint32_t result = kNone;          // the result's register; kNone for void (sceneSetup)
};

struct Program {
    std::vector<Instr> code;
    std::vector<std::array<float, 4>> constants;
    std::vector<Entry> entries;
    std::vector<std::string> uniforms;  // slot -> uniform name: the uniformSlots Translate() was given
    uint32_t registers = 0;             // registers used, globals included (<= kMaxRegisters)
    uint32_t globals = 0;               // registers [0, globals) keep their values between calls
    const Entry* Find(const std::string& name) const;
};

// The code buffer the GPU reads (render/eval.glsl): HookNames().size() header uvec4s, one per hook
// in HookNames() order: (pc, first argument's register, result register, 1 if the scene has it),
// then the code. Instruction i is at [HookNames().size() + i]; jump targets are instruction indices.
std::vector<std::array<uint32_t, 4>> PackCode(const Program& program);

// The scene hooks the renderer calls (render/render.glsl, march.glsl): every one the scene defines
// becomes an entry. Their signatures are the renderer's.
const std::vector<std::string>& HookNames();

// The uniforms a scene's evaluator code may read, in slot order: the built-in uniforms of
// render/uniforms.glsl in declaration order (those under #if included), then the scene's inputs
// u_<NAME> in header order. Depends on the scene's header only, so it is fixed for a scene shape.
std::vector<std::string> UniformSlots(const SceneInfo& scene);

// The unit Translate() reads for a scene: "#version 450 core", the variant's defines, then
// SCENE_SETUP_FRAME 0 and SCENE_TABLES 0 (the evaluator runs a scene's setup per invocation and
// computes its tables where it needs them), the built-in uniforms, the scene's input uniforms (as
// AssembleProgram declares them), the scene with its includes expanded, and a compute main() that
// calls every hook the scene defines (so glslang keeps them). A last comment line names the unit's
// files, for Translate()'s messages. uniformSlots: UniformSlots(scene).
bool AssembleEvaluatorUnit(const SceneInfo& scene, const VariantKey& key, std::string* unit,
                           std::vector<std::string>* uniformSlots, std::string* error);

// Translates `unit` (a whole GLSL compute or fragment shader source, #version first, whose main()
// calls every hook it defines, so glslang keeps them) into `out`. false with "line: what" in
// `error` when glslang rejects the text or it uses what the machine lacks (a texture, a loop the
// registers cannot hold): the caller then builds the scene's program as before.
// uniformSlots: the uniforms the machine can read, in slot order (UniformSlots(): the built-in
// uniforms, then the scene's inputs), fixed for a scene shape so the GPU program's slot table
// (render/eval.glsl's evalUniform) stays valid across saves. A uniform outside it fails.
bool Translate(const std::string& unit, const std::vector<std::string>& uniformSlots, Program* out,
               std::string* error);

// glslang's first compile in a process sets up its built-in symbol tables: ~200 ms, against
// 4-9 ms for each later scene. Call this once at start-up (any thread) so a save never pays it.
void PrepareTranslator();

// Runs entry `name` on the CPU (tests; the same machine as render/eval.glsl). `registers` holds the
// invocation's registers (its globals kept between calls); `uniform(slot)` gives a uniform's value.
struct Machine {
    std::vector<std::array<float, 4>> R = std::vector<std::array<float, 4>>(kMaxRegisters, {0, 0, 0, 0});
    std::vector<std::array<float, 4>> uniformValues;  // by slot
};
bool Run(const Program& program, const std::string& name, const std::vector<std::array<float, 4>>& args, Machine* m,
         std::array<float, 4>* result, std::string* error);

}  // namespace sdfvj::eval
