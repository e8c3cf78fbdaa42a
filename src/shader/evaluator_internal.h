// Internal to the evaluator (evaluator*.cpp): the glslang front end and the SPIR-V translation.
#pragma once
#include <string>
#include <vector>

#include "shader/evaluator.h"

namespace sdfvj::eval {

// GLSL -> SPIR-V words with glslang (OpenGL 4.5 client, SPIR-V 1.0, no optimizer, OpLine kept so
// a rejected construct can name its line). false with glslang's log, lines mapped, in `error`.
bool CompileSpirv(const std::string& unit, std::vector<uint32_t>* words, std::string* error);

// The SPIR-V module's hooks -> machine code (evaluator_translate.cpp). `where(line)` names a
// unit line for messages ("shaders/scenes/midi.glsl:42").
struct UnitFiles {
    std::string name;                 // the unit's scene file, or "unit"
    std::vector<std::string> files;   // #line source-string index -> file
    std::string Where(uint32_t line) const;
};
// Code before register allocation: operands name a virtual register group (a value or variable
// of one or more consecutive registers) and a register in it, or a constant.
struct Opnd {
    uint32_t group = kNone;   // kNone: no operand (or a constant)
    uint32_t off = 0;         // register in the group, or the constant's index
    bool isConst = false;
    uint32_t lane = 0;        // a register read as one lane in all four: 1-4 (x..w); 0: the whole register
    bool Used() const { return isConst || group != kNone; }
};
struct VInstr {
    uint32_t op = kNop;
    Opnd dst, a, b, c;
    uint32_t imm = 0;
    Opnd immReg;                 // kLoadIndexed / kStoreIndexed: imm = this register's number
    uint32_t label = kNone;      // jumps: imm = this label's pc
    uint32_t returnGroup = kNone;   // kReturn: the entry's result, read by the caller
    bool kill = false;           // writes all of dst's group (liveness: no earlier value lives on)
};
struct Group {
    uint32_t size = 1;
    int fixed = -1;              // a SCENE_STATE global's register, outside the allocation
    int reg = -1;                // the allocated first register
};
// Liveness over the linear code and allocation of the groups into [globals, kMaxRegisters); then
// the final Instrs (evaluator_regalloc.cpp). `pins`: groups that must hold a register at a pc (an
// entry's arguments at its first instruction, even when unread).
bool AllocateRegisters(std::vector<VInstr>& code, std::vector<Group>& groups,
                       const std::vector<std::pair<uint32_t, uint32_t>>& pins, const std::vector<uint32_t>& labelPc,
                       uint32_t globals, Program* out, std::string* error);

// Removes instructions whose results nothing reads (unoptimized SPIR-V stores every argument and
// local to a variable; with loads forwarded from stores many of those stores are dead), and
// renumbers labels and `pcs` (entry points) to match. Globals' writes and control flow are kept.
void RemoveDeadCode(std::vector<VInstr>& code, const std::vector<Group>& groups, std::vector<uint32_t>& labelPc,
                    const std::vector<uint32_t*>& pcs);

// Removes the copies kMov makes, within basic blocks, where exact (evaluator_copies.cpp): a copy's
// later reads read its source; a temporary read only by the copy after it is written to the copy's
// register instead. Copies nothing reads any more are left for RemoveDeadCode. labelPc and `pcs`
// (entry points) mark where blocks start.
void PropagateCopies(std::vector<VInstr>& code, const std::vector<Group>& groups, const std::vector<uint32_t>& labelPc,
                     const std::vector<uint32_t*>& pcs);

bool TranslateSpirv(const std::vector<uint32_t>& words, const std::vector<std::string>& uniformSlots,
                    const UnitFiles& files, Program* out, std::string* error);

}  // namespace sdfvj::eval
