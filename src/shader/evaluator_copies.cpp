// Copies out of the evaluator's code before register allocation (evaluator_internal.h).
//
// Unoptimized SPIR-V moves every value through variables, and inlining moves every argument and
// result: a third to two fifths of the translated instructions were kMov (midi 232 of 694,
// character 1448 of 3567), and each costs the GPU machine a whole dispatch. A fifth more were
// kSwizzle putting one lane in all four (a component extracted: p.y). Two rewrites, each within a
// basic block, where they are plainly exact:
// - forward: after `MOV d = s`, a later read of d reads s, until d or s is written again; after
//   `SWIZZLE d = s.yyyy`, a later read of d reads s's lane y (an operand's lane, evaluator.h);
// - backward: `op t = ..; ..; MOV x = t`, with t read by that MOV alone and x neither read nor
//   written in between, becomes `op x = ..` (the MOV goes).
// RemoveDeadCode then drops the copies nothing reads any more.
#include <unordered_map>

#include "shader/evaluator_internal.h"

namespace sdfvj::eval {

namespace {

bool IsJumpOp(uint32_t op) { return op == kJump || op == kJumpIfZero || op == kJumpIfNotZero; }

bool IsReg(const Opnd& o) { return !o.isConst && o.group != kNone; }

// The group an instruction writes (kNone: none): dst, or the array a kStoreIndexed writes.
uint32_t Written(const VInstr& in) {
    const Opnd& d = in.op == kStoreIndexed ? in.immReg : in.dst;
    return IsReg(d) ? d.group : kNone;
}

// True when `in` reads `group` (its operands, an indexed array, a partial write's own register,
// the entry's result at a return).
bool Reads(const VInstr& in, uint32_t group) {
    for (const Opnd* o : {&in.a, &in.b, &in.c})
        if (IsReg(*o) && o->group == group) return true;
    if ((in.op == kLoadIndexed || in.op == kStoreIndexed) && IsReg(in.immReg) && in.immReg.group == group) return true;
    if ((in.op == kSetComp || !in.kill) && IsReg(in.dst) && in.dst.group == group) return true;
    return in.returnGroup == group;
}

// A whole single register, read whole: what the rewrites move values between.
bool Single(const Opnd& o, const std::vector<Group>& groups) {
    return IsReg(o) && o.off == 0 && o.lane == 0 && groups[o.group].size == 1;
}

}  // namespace

void PropagateCopies(std::vector<VInstr>& code, const std::vector<Group>& groups, const std::vector<uint32_t>& labelPc,
                     const std::vector<uint32_t*>& pcs) {
    const size_t n = code.size();
    std::vector<char> leader(n + 1, 0);
    for (const VInstr& in : code)   // a label no jump names starts no block
        if (IsJumpOp(in.op) && in.label != kNone && labelPc[in.label] <= n) leader[labelPc[in.label]] = 1;
    for (const uint32_t* pc : pcs)
        if (*pc <= n) leader[*pc] = 1;
    for (size_t i = 0; i < n; ++i)
        if (IsJumpOp(code[i].op) || code[i].op == kReturn) leader[i + 1] = 1;

    // Forward: reads of a copy read its source.
    std::unordered_map<uint32_t, Opnd> copyOf;   // group -> the value it holds a copy of (a lane of it in all four)
    for (size_t i = 0; i < n; ++i) {
        if (leader[i]) copyOf.clear();
        VInstr& in = code[i];
        for (Opnd* o : {&in.a, &in.b, &in.c}) {
            if (!IsReg(*o) || o->off != 0) continue;
            const auto it = copyOf.find(o->group);
            if (it == copyOf.end()) continue;
            const Opnd& src = it->second;
            if (src.lane != 0 || o->lane == 0) {
                *o = src;   // every lane of the copy is the source's lane, or the whole copy is read
            } else if (!src.isConst) {
                const uint32_t lane = o->lane;   // one lane of a whole copy: that lane of its source
                *o = src;
                o->lane = lane;
            }   // one lane of a copied constant: a constant has no lanes to pick, the read stays
        }
        const uint32_t w = Written(in);
        if (w != kNone) {
            copyOf.erase(w);
            for (auto it = copyOf.begin(); it != copyOf.end();)
                it = IsReg(it->second) && it->second.group == w ? copyOf.erase(it) : std::next(it);
        }
        if (!Single(in.dst, groups) || (IsReg(in.a) && in.a.group == in.dst.group)) continue;
        if (in.op == kMov && in.a.Used()) copyOf[in.dst.group] = in.a;
        // A swizzle that puts one lane of a register in all four: its readers read that lane.
        if (in.op == kSwizzle && IsReg(in.a) && !in.b.Used() && !in.c.Used()) {
            const uint32_t lane = in.imm & 7u;
            if (lane < 4 && in.imm == lane * 01111u) {
                Opnd src = in.a;
                if (src.lane == 0) src.lane = lane + 1;   // a lane of a broadcast is the broadcast
                copyOf[in.dst.group] = src;
            }
        }
    }

    // Backward: a temporary read only by the copy that follows it is written straight to the copy.
    std::vector<uint32_t> reads(groups.size(), 0);
    for (const VInstr& in : code) {
        for (const Opnd* o : {&in.a, &in.b, &in.c})
            if (IsReg(*o)) ++reads[o->group];
        if ((in.op == kLoadIndexed || in.op == kStoreIndexed) && IsReg(in.immReg)) ++reads[in.immReg.group];
        if ((in.op == kSetComp || !in.kill) && IsReg(in.dst)) ++reads[in.dst.group];
        if (in.returnGroup != kNone) ++reads[in.returnGroup];
    }
    for (size_t i = 0; i < n; ++i) {
        VInstr& mov = code[i];
        if (mov.op != kMov || !Single(mov.dst, groups) || !Single(mov.a, groups) || mov.a.group == mov.dst.group) continue;
        const uint32_t t = mov.a.group, x = mov.dst.group;
        if (groups[t].fixed >= 0 || reads[t] != 1) continue;
        // The write of t this copy reads: the last before it in its block.
        size_t j = i;
        bool clear = true;   // x untouched between
        while (j > 0 && !leader[j]) {
            --j;
            if (Written(code[j]) == t) break;
            if (Written(code[j]) == x || Reads(code[j], x)) clear = false;
        }
        VInstr& def = code[j];
        if (j == i || Written(def) != t || !clear || def.op == kSetComp || def.op == kStoreIndexed || !def.kill ||
            def.dst.off != 0)
            continue;
        def.dst = mov.dst;
        def.kill = mov.kill;
        // The copy now writes t, which nothing reads: RemoveDeadCode drops it.
        mov.dst = Opnd{t, 0, false};
        mov.a = Opnd{};
        reads[t] = 0;
    }
}

}  // namespace sdfvj::eval
