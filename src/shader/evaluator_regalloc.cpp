// Register allocation for the evaluator's code (evaluator.h): liveness over the linear code, then a
// linear scan over each group's live hull. The hull (first to last pc where the group is live, read
// or written) is conservative inside loops and branches, and simple: a group of several registers
// (a matrix, a struct, an array) is one unit with one contiguous range, which kLoadIndexed needs.
#include <algorithm>
#include <bitset>

#include "shader/evaluator_internal.h"

namespace sdfvj::eval {

namespace {

struct Bits {
    std::vector<uint64_t> w;
    explicit Bits(size_t n = 0) : w((n + 63) / 64, 0) {}
    bool Get(uint32_t i) const { return (w[i >> 6] >> (i & 63)) & 1; }
    void Set(uint32_t i) { w[i >> 6] |= uint64_t(1) << (i & 63); }
};

bool IsJump(uint32_t op) { return op == kJump || op == kJumpIfZero || op == kJumpIfNotZero; }
bool EndsBlock(uint32_t op) { return IsJump(op) || op == kReturn; }

// The groups an instruction reads and writes (fixed groups, the globals, are left out: they live
// throughout).
void UsesDefs(const VInstr& in, const std::vector<Group>& groups, std::vector<uint32_t>* uses,
              std::vector<uint32_t>* defs) {
    uses->clear();
    defs->clear();
    auto add = [&](std::vector<uint32_t>* v, const Opnd& o) {
        if (!o.isConst && o.group != kNone && groups[o.group].fixed < 0) v->push_back(o.group);
    };
    add(uses, in.a);
    add(uses, in.b);
    add(uses, in.c);
    if (in.op == kSetComp || !in.kill) add(uses, in.dst);   // a partial write keeps the rest
    if (in.op == kLoadIndexed) add(uses, in.immReg);
    if (in.op == kStoreIndexed) {
        add(uses, in.immReg);
        add(defs, in.immReg);
    }
    if (in.returnGroup != kNone && groups[in.returnGroup].fixed < 0) uses->push_back(in.returnGroup);
    add(defs, in.dst);
}

}  // namespace

void RemoveDeadCode(std::vector<VInstr>& code, const std::vector<Group>& groups, std::vector<uint32_t>& labelPc,
                    const std::vector<uint32_t*>& pcs) {
    const size_t n = code.size();
    std::vector<char> keep(n, 1);
    auto removable = [&](const VInstr& in, uint32_t* group) {
        if (IsJump(in.op) || in.op == kReturn) return false;
        const Opnd& d = in.op == kStoreIndexed ? in.immReg : in.dst;
        if (d.isConst || d.group == kNone || groups[d.group].fixed >= 0) return false;
        *group = d.group;
        return true;
    };
    for (bool changed = true; changed;) {
        changed = false;
        std::vector<uint32_t> reads(groups.size(), 0);
        auto read = [&](const Opnd& o) {
            if (!o.isConst && o.group != kNone) ++reads[o.group];
        };
        for (size_t i = 0; i < n; ++i) {
            if (!keep[i]) continue;
            const VInstr& in = code[i];
            // A group's reads by its own partial writes (kSetComp, a swizzle that keeps lanes) do
            // not keep it alive.
            const uint32_t self = in.dst.isConst ? kNone : in.dst.group;
            for (const Opnd* o : {&in.a, &in.b, &in.c})
                if (o->isConst || o->group != self) read(*o);
            if (in.op == kLoadIndexed) read(in.immReg);
            if (in.returnGroup != kNone) ++reads[in.returnGroup];
        }
        for (size_t i = 0; i < n; ++i) {
            uint32_t g;
            if (keep[i] && removable(code[i], &g) && reads[g] == 0) {
                keep[i] = 0;
                changed = true;
            }
        }
    }
    std::vector<uint32_t> newPc(n + 1);
    std::vector<VInstr> kept;
    for (size_t i = 0; i < n; ++i) {
        newPc[i] = (uint32_t)kept.size();
        if (keep[i]) kept.push_back(code[i]);
    }
    newPc[n] = (uint32_t)kept.size();
    for (uint32_t& pc : labelPc)
        if (pc != kNone) pc = newPc[pc];
    for (uint32_t* pc : pcs) *pc = newPc[*pc];
    code = std::move(kept);
}

bool AllocateRegisters(std::vector<VInstr>& code, std::vector<Group>& groups,
                       const std::vector<std::pair<uint32_t, uint32_t>>& pins, const std::vector<uint32_t>& labelPc,
                       uint32_t globals, Program* out, std::string* error) {
    const uint32_t n = (uint32_t)code.size(), G = (uint32_t)groups.size();
    for (VInstr& in : code)
        if (in.label != kNone) in.imm = labelPc[in.label];
    // Basic blocks: a jump target or the instruction after a jump or return starts one.
    std::vector<char> leader(n + 1, 0);
    leader[0] = 1;
    for (uint32_t i = 0; i < n; ++i) {
        if (IsJump(code[i].op) && code[i].imm < n) leader[code[i].imm] = 1;
        if (EndsBlock(code[i].op)) leader[i + 1] = 1;
    }
    std::vector<uint32_t> start, blockOf(n);
    for (uint32_t i = 0; i < n; ++i) {
        if (leader[i]) start.push_back(i);
        blockOf[i] = (uint32_t)start.size() - 1;
    }
    const uint32_t B = (uint32_t)start.size();
    auto endOf = [&](uint32_t b) { return b + 1 < B ? start[b + 1] - 1 : n - 1; };
    std::vector<Bits> gen(B, Bits(G)), kill(B, Bits(G)), in(B, Bits(G)), outB(B, Bits(G));
    std::vector<std::vector<uint32_t>> succ(B);
    std::vector<uint32_t> uses, defs;
    std::vector<uint32_t> first(G, UINT32_MAX), last(G, 0);
    auto touch = [&](uint32_t g, uint32_t pc) {
        first[g] = std::min(first[g], pc);
        last[g] = std::max(last[g], pc);
    };
    for (uint32_t b = 0; b < B; ++b) {
        for (uint32_t i = start[b]; i <= endOf(b); ++i) {
            UsesDefs(code[i], groups, &uses, &defs);
            for (uint32_t g : uses) {
                touch(g, i);
                if (!kill[b].Get(g)) gen[b].Set(g);
            }
            for (uint32_t g : defs) touch(g, i);
            if (code[i].kill && code[i].op != kSetComp)
                for (uint32_t g : defs) kill[b].Set(g);
        }
        const VInstr& lastIn = code[endOf(b)];
        if (IsJump(lastIn.op) && lastIn.imm < n) succ[b].push_back(blockOf[lastIn.imm]);
        if (lastIn.op != kJump && lastIn.op != kReturn && endOf(b) + 1 < n) succ[b].push_back(b + 1);
    }
    const size_t words = (G + 63) / 64;
    for (bool changed = true; changed;) {
        changed = false;
        for (uint32_t b = B; b-- > 0;) {
            for (uint32_t s : succ[b])
                for (size_t k = 0; k < words; ++k) outB[b].w[k] |= in[s].w[k];
            for (size_t k = 0; k < words; ++k) {
                const uint64_t v = gen[b].w[k] | (outB[b].w[k] & ~kill[b].w[k]);
                if (v != in[b].w[k]) {
                    in[b].w[k] = v;
                    changed = true;
                }
            }
        }
    }
    for (uint32_t b = 0; b < B; ++b)
        for (size_t k = 0; k < words; ++k) {
            for (uint64_t v = in[b].w[k]; v; v &= v - 1) touch(uint32_t(k * 64 + __builtin_ctzll(v)), start[b]);
            for (uint64_t v = outB[b].w[k]; v; v &= v - 1) touch(uint32_t(k * 64 + __builtin_ctzll(v)), endOf(b));
        }
    for (auto [g, pc] : pins) touch(g, pc);
    // Linear scan: by start; a register is free again after the last pc of its group (never at the
    // same pc, so an instruction's operands and result never share a register).
    std::vector<uint32_t> order;
    for (uint32_t g = 0; g < G; ++g)
        if (groups[g].fixed < 0 && first[g] != UINT32_MAX) order.push_back(g);
    std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) { return first[x] < first[y]; });
    std::vector<uint32_t> active;
    std::bitset<kMaxRegisters> used;
    for (uint32_t r = 0; r < globals; ++r) used.set(r);
    uint32_t top = globals;
    for (uint32_t g : order) {
        for (size_t k = 0; k < active.size();) {
            const uint32_t a = active[k];
            if (last[a] < first[g]) {
                for (uint32_t r = 0; r < groups[a].size; ++r) used.reset(groups[a].reg + r);
                active[k] = active.back();
                active.pop_back();
            } else {
                ++k;
            }
        }
        const uint32_t size = groups[g].size;
        int found = -1;
        for (uint32_t r = globals; r + size <= kMaxRegisters && found < 0; ++r) {
            uint32_t k = 0;
            while (k < size && !used.test(r + k)) ++k;
            if (k == size) found = (int)r;
            else r += k;
        }
        if (found < 0) {
            *error = "needs more than " + std::to_string(kMaxRegisters) + " registers (" + std::to_string(globals) +
                     " of them the scene's SCENE_STATE globals)";
            return false;
        }
        groups[g].reg = found;
        for (uint32_t r = 0; r < size; ++r) used.set(found + r);
        top = std::max(top, (uint32_t)found + size);
        active.push_back(g);
    }
    auto reg = [&](const Opnd& o) -> uint32_t {
        if (o.isConst) return kConstFlag | o.off;
        if (o.group == kNone) return kNone;
        const Group& gr = groups[o.group];
        return (uint32_t)((gr.fixed >= 0 ? gr.fixed : std::max(gr.reg, (int)globals)) + (int)o.off) | (o.lane << kLaneShift);
    };
    out->code.clear();
    for (const VInstr& v : code) {
        Instr i;
        i.op = v.op;
        i.dst = reg(v.dst);
        i.a = reg(v.a);
        i.b = reg(v.b);
        i.c = reg(v.c);
        i.imm = (v.op == kLoadIndexed || v.op == kStoreIndexed) ? reg(v.immReg) : v.imm;
        out->code.push_back(i);
    }
    out->registers = top;
    out->globals = globals;
    return true;
}

}  // namespace sdfvj::eval
