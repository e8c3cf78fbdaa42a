// eval.glsl - the scene evaluator's register machine on the GPU (issue 12). Its specification is
// src/shader/evaluator.h (opcodes, operand encoding, the packed instruction, the code buffer's
// header); src/shader/eval_program.cpp assembles the program around it: the renderer with the
// scene's hook functions' bodies replaced by calls into this machine, so a save that edits what
// the hooks compute is drawn by uploading new code, with no driver build.
//
// Included by that program only, after what eval_program.cpp generates in front of it: the
// opcodes as `const uint EV_<OP>` (from the C++ enum, so the two cannot drift apart), the hooks'
// header slots EV_HOOK_<NAME> (evaluator.h HookNames() order), EV_HOOKS (the header's length),
// EV_CODE_BINDING / EV_CONST_BINDING (scene.h kEvalCodeBinding, kEvalConstBinding),
// EV_MAX_REGISTERS, EV_NONE, EV_CONST_FLAG, EV_LANE_SHIFT and `vec4 evalUniform(uint slot)` (the scene's uniform
// slot table: eval::UniformSlots order).
#ifndef SDF_RENDER_EVAL_GLSL
#define SDF_RENDER_EVAL_GLSL

// The code: EV_HOOKS header entries (pc, first argument's register, result register, present),
// then one instruction per uvec4 (op, dst | a << 16, b | c << 16, imm). The constants: vec4s.
layout(std430, binding = EV_CODE_BINDING) readonly buffer EvalCode { uvec4 ev_code[]; };
layout(std430, binding = EV_CONST_BINDING) readonly buffer EvalConst { vec4 ev_const[]; };

// The registers, private to the invocation: [0, globals) keep the scene's SCENE_STATE between
// calls (sceneSetup writes them, map reads them), the rest is scratch.
vec4 ev_R[EV_MAX_REGISTERS];
const uint EV_REGISTER_MASK = EV_MAX_REGISTERS - 1u;   // a power of two: an index out of range wraps, never leaves the array

// Instructions an invocation may execute in all its calls: code that loops for ever (a bad buffer,
// a translator's bug) ends the pixel's calls, not the GPU's work. The heaviest pixel of a shipped
// scene runs 210,000 (field50, its own effects; 325,000 with a mirror bounce): 50 times below this.
// (llvmpipe's own bound comes first there: EV_UNROLL.)
const uint EV_MAX_STEPS = 1u << 24;
uint ev_steps = 0u;

// An operand: a register (one lane of it in all four when bits 12-14 name one), a constant (bit
// 15), or none (0xffff, read as 0). Indices are kept in range, so a bad buffer reads wrong values
// rather than memory outside the arrays.
vec4 evalOperand(uint o, uint constants) {
    if (o == EV_NONE) return vec4(0.0);
    if ((o & EV_CONST_FLAG) != 0u) {
        uint k = o & 0x7fffu;
        return k < constants ? ev_const[k] : vec4(0.0);
    }
    vec4 v = ev_R[o & EV_REGISTER_MASK];
    uint lane = (o >> EV_LANE_SHIFT) & 7u;   // the same for every invocation at this instruction
    if (lane != 0u) v = vec4(v[(lane - 1u) & 3u]);
    return v;
}

// One instruction at `pc` (which it moves on); false when the call has ended (kReturn, or a pc
// past the code).
bool evalStep(inout uint pc, uint instructions, uint constants) {
    vec4 Z = vec4(0.0);
    uint at = EV_HOOKS + pc;
    if (at >= instructions) return false;
    uvec4 ins = ev_code[at];
    pc++;
    uint dst = ins.y & 0xffffu, imm = ins.w;
    // Every operand is fetched whatever the op: one fetch site (a smaller switch), and an
    // unused operand is EV_NONE, which reads nothing.
    vec4 A = evalOperand(ins.y >> 16u, constants), B = evalOperand(ins.z & 0xffffu, constants),
         C = evalOperand(ins.z >> 16u, constants);
    vec4 r = vec4(0.0);
    bool write = true;   // r goes to R[dst]
    switch (ins.x) {
    case EV_NOP: write = false; break;
    case EV_MOV: r = A; break;
    case EV_SWIZZLE:
        for (uint i = 0u; i < 4u; i++) {
            uint sel = (imm >> (3u * i)) & 7u;
            r[i] = sel < 4u ? A[sel] : B[sel & 3u];
        }
        break;
    case EV_SET_COMP: r = ev_R[dst & EV_REGISTER_MASK]; r[imm & 3u] = A.x; break;
    case EV_LOAD_UNIFORM: r = evalUniform(imm); break;
    case EV_LOAD_INDEXED: r = ev_R[(imm + uint(int(A.x))) & EV_REGISTER_MASK]; break;
    case EV_STORE_INDEXED: ev_R[(imm + uint(int(A.x))) & EV_REGISTER_MASK] = B; write = false; break;
    case EV_ADD: r = A + B; break;
    case EV_SUB: r = A - B; break;
    case EV_MUL: r = A * B; break;
    case EV_DIV: r = A / B; break;
    case EV_NEG: r = -A; break;
    case EV_FMA: r = A * B + C; break;
    case EV_MOD: r = A - B * floor(A / B); break;
    case EV_MIN: r = min(A, B); break;
    case EV_MAX: r = max(A, B); break;
    case EV_CLAMP: r = clamp(A, B, C); break;
    case EV_MIX: r = mix(A, B, C); break;
    case EV_STEP: r = step(A, B); break;
    case EV_SMOOTHSTEP: r = smoothstep(A, B, C); break;
    case EV_ABS: r = abs(A); break;
    case EV_SIGN: r = sign(A); break;
    case EV_FLOOR: r = floor(A); break;
    case EV_CEIL: r = ceil(A); break;
    case EV_FRACT: r = fract(A); break;
    case EV_ROUND: r = round(A); break;
    case EV_TRUNC: r = trunc(A); break;
    case EV_SQRT: r = sqrt(A); break;
    case EV_INVERSE_SQRT: r = inversesqrt(A); break;
    case EV_EXP: r = exp(A); break;
    case EV_EXP2: r = exp2(A); break;
    case EV_LOG: r = log(A); break;
    case EV_LOG2: r = log2(A); break;
    case EV_POW: r = pow(A, B); break;
    case EV_SIN: r = sin(A); break;
    case EV_COS: r = cos(A); break;
    case EV_TAN: r = tan(A); break;
    case EV_ASIN: r = asin(A); break;
    case EV_ACOS: r = acos(A); break;
    case EV_ATAN: r = atan(A); break;
    case EV_ATAN2: r = atan(A, B); break;
    // The built-in dot of the lanes the op names: the compiled scene's own arithmetic.
    case EV_DOT: r = vec4(imm == 2u ? dot(A.xy, B.xy) : imm == 3u ? dot(A.xyz, B.xyz) : dot(A, B)); break;
    case EV_CROSS: r = vec4(cross(A.xyz, B.xyz), ev_R[dst & EV_REGISTER_MASK].w); break;   // dst.w kept (the CPU machine's)
    case EV_LESS: r = vec4(lessThan(A, B)); break;
    case EV_LESS_EQUAL: r = vec4(lessThanEqual(A, B)); break;
    case EV_GREATER: r = vec4(greaterThan(A, B)); break;
    case EV_GREATER_EQUAL: r = vec4(greaterThanEqual(A, B)); break;
    case EV_EQUAL: r = vec4(equal(A, B)); break;
    case EV_NOT_EQUAL: r = vec4(notEqual(A, B)); break;
    case EV_AND: r = vec4(notEqual(A, Z)) * vec4(notEqual(B, Z)); break;
    case EV_OR: r = max(vec4(notEqual(A, Z)), vec4(notEqual(B, Z))); break;
    case EV_NOT: r = vec4(equal(A, Z)); break;
    case EV_SELECT: r = mix(B, A, notEqual(C, Z)); break;   // a selection, not arithmetic: inf and NaN pass unharmed
    case EV_INT_DIV: r = trunc(A / B); break;
    case EV_INT_REM: r = A - B * trunc(A / B); break;
    // Powers of two by the exponent (ldexp): exact, where exp2 may round.
    case EV_SHIFT_RIGHT: r = floor(ldexp(A, -ivec4(B))); break;
    case EV_SHIFT_LEFT: r = ldexp(A, ivec4(B)); break;
    case EV_BIT_AND: r = vec4(uvec4(A) & uvec4(B)); break;
    case EV_BIT_OR: r = vec4(uvec4(A) | uvec4(B)); break;
    case EV_BIT_XOR: r = vec4(uvec4(A) ^ uvec4(B)); break;
    case EV_ANY:
    case EV_ALL: {
        // The first imm lanes: the others count as false for any, true for all.
        bvec4 lanes = lessThan(uvec4(0u, 1u, 2u, 3u), uvec4(imm));
        uvec4 set = uvec4(notEqual(A, Z));
        bool result = ins.x == EV_ANY ? any(bvec4(set & uvec4(lanes))) : all(bvec4(set | uvec4(not(lanes))));
        r = vec4(result ? 1.0 : 0.0);
        break;
    }
    case EV_JUMP: pc = imm; write = false; break;
    case EV_JUMP_IF_ZERO: if (A.x == 0.0) pc = imm; write = false; break;
    case EV_JUMP_IF_NOT_ZERO: if (A.x != 0.0) pc = imm; write = false; break;
    case EV_RETURN: return false;
    default: write = false; break;   // an op this machine lacks: skipped
    }
    if (write) ev_R[dst & EV_REGISTER_MASK] = r;
    return true;
}

// Instructions run per iteration of the machine's loop in a field hook's call (1, 2, 4, 8 or 16;
// AssembleEvaluatorProgram's `unroll`): 1 on a GPU. llvmpipe ends a shader's loops after 65535
// iterations in all (LP_MAX_TGSI_LOOP_ITERATIONS, "shared between every loop"): at one instruction
// an iteration a pixel of midi's silhouette or of mandelbulb (up to 157,000 instructions with its
// own effects) runs past that, and its last calls return what their registers happened to hold.
// There kEvaluatorUnrollSoftware (4): each copy of the loop is 4 copies of the machine for the
// compiler, so only the objects' call site has it (the floor's places and the setup's run one an
// iteration): llvmpipe builds midi's program in 2.9 s instead of 1.8 s (19 s with the floor
// unrolled too; 8 everywhere: 13-50 s).
#ifndef EV_UNROLL
#define EV_UNROLL 1
#endif
#define EV_STEP if (!evalStep(pc, instructions, constants)) break;

// Runs the code from instruction `pc` to its kReturn.
void evalRun(uint pc) {
    uint instructions = uint(ev_code.length()), constants = uint(ev_const.length());
    while (ev_steps < EV_MAX_STEPS) {
        ev_steps += uint(EV_UNROLL);
        EV_STEP
#if EV_UNROLL >= 2
        EV_STEP
#endif
#if EV_UNROLL >= 4
        EV_STEP EV_STEP
#endif
#if EV_UNROLL >= 8
        EV_STEP EV_STEP EV_STEP EV_STEP
#endif
#if EV_UNROLL >= 16
        EV_STEP EV_STEP EV_STEP EV_STEP EV_STEP EV_STEP EV_STEP EV_STEP
#endif
    }
}
// The same, an instruction an iteration: the setup and the argument-less hooks (a few hundred
// instructions an invocation, one copy of the machine).
void evalRunEach(uint pc) {
    uint instructions = uint(ev_code.length()), constants = uint(ev_const.length());
    while (ev_steps < EV_MAX_STEPS) {
        ev_steps++;
        EV_STEP
    }
}

// A call of hook `hook` (its header entry): the argument to its register, the code run, the
// result read back. A hook the code lacks (or no code bound) answers 0. evalCallEach: the same with
// one instruction an iteration.
vec4 evalCall(uint hook, vec4 arg) {
    if (hook >= uint(ev_code.length())) return vec4(0.0);
    uvec4 e = ev_code[hook];
    if (e.w == 0u) return vec4(0.0);
    if (e.y != EV_NONE) ev_R[e.y & EV_REGISTER_MASK] = arg;
    evalRun(e.x);
    return e.z != EV_NONE ? ev_R[e.z & EV_REGISTER_MASK] : vec4(0.0);
}
vec4 evalCallEach(uint hook, vec4 arg) {
    if (hook >= uint(ev_code.length())) return vec4(0.0);
    uvec4 e = ev_code[hook];
    if (e.w == 0u) return vec4(0.0);
    if (e.y != EV_NONE) ev_R[e.y & EV_REGISTER_MASK] = arg;
    evalRunEach(e.x);
    return e.z != EV_NONE ? ev_R[e.z & EV_REGISTER_MASK] : vec4(0.0);
}

// The hooks without arguments depend on uniforms and the scene's state only: they are run once per
// invocation, after the scene's setup (render.glsl callSceneSetup calls evalPrepare first thing,
// before any field call), and answered from here. The renderer reads sceneBound() at every march
// step (boundDistance): run there, it would double the machine's work; and this loop is one copy
// of the machine for all six.
vec4 ev_bound, ev_lipschitz, ev_groundBlend, ev_boxMin, ev_boxMax;
void evalPrepare() {
    for (int i = SDF_LOOP_ZERO; i < 6; i++) {   // rolled: one copy of the machine
        uint hook = i == 0 ? EV_HOOK_SCENE_SETUP : i == 1 ? EV_HOOK_SCENE_BOUND : i == 2 ? EV_HOOK_SCENE_LIPSCHITZ
                  : i == 3 ? EV_HOOK_SCENE_GROUND_BLEND : i == 4 ? EV_HOOK_SCENE_BOX_MIN : EV_HOOK_SCENE_BOX_MAX;
        vec4 r = evalCallEach(hook, vec4(0.0));
        if (i == 1) ev_bound = r;
        else if (i == 2) ev_lipschitz = r;
        else if (i == 3) ev_groundBlend = r;
        else if (i == 4) ev_boxMin = r;
        else if (i == 5) ev_boxMax = r;
    }
}

// What the scene's stubbed hooks call (eval_program.cpp writes `vec4 map(vec3 p) { return evalMap(p); }`).
vec4 evalMap(vec3 p) { return evalCall(EV_HOOK_MAP, vec4(p, 0.0)); }
// The floor: a few instructions (render.glsl: the plane y = 0 alone, its albedo), read at several
// places in the renderer (the march's stretch, the ground snap, the one-site loop twice): one
// instruction an iteration, so each place is one copy of the machine however EV_UNROLL is set.
vec4 evalMapGround(vec3 p) { return evalCallEach(EV_HOOK_MAP_GROUND, vec4(p, 0.0)); }
vec4 evalMapObjects(vec3 p) { return evalCall(EV_HOOK_MAP_OBJECTS, vec4(p, 0.0)); }
vec4 evalSceneBound() { return ev_bound; }
float evalSceneLipschitz() { return ev_lipschitz.x; }
float evalSceneGroundBlend() { return ev_groundBlend.x; }
vec3 evalSceneBoxMin() { return ev_boxMin.xyz; }
vec3 evalSceneBoxMax() { return ev_boxMax.xyz; }
void evalSceneSetup() { evalCallEach(EV_HOOK_SCENE_SETUP, vec4(0.0)); }

#endif
