// Primitive tests of the shared GLSL SDF library, in float (sdf32) and double (sdf64).
#include <catch2/catch.hpp>

#include <functional>
#include <vector>

#include "reference_geometry.h"
#include "sdf/sdf32.h"
#include "sdf/sdf64.h"

#define NS sdf32
#define PREC "float"
#define TOL 2e-5
#define CASES_NS cases32
#include "lib_cases.inc"
#undef NS
#undef PREC
#undef TOL
#undef CASES_NS

#define NS sdf64
#define PREC "double"
#define TOL 1e-9
#define CASES_NS cases64
#include "lib_cases.inc"
#undef NS
#undef PREC
#undef TOL
#undef CASES_NS
