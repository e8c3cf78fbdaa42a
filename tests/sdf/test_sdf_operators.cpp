// Domain operator and combinator tests, in float (sdf32) and double (sdf64).
#include <catch2/catch.hpp>

#include "reference_geometry.h"
#include "sdf/sdf32.h"
#include "sdf/sdf64.h"

#define NS sdf32
#define PREC "float"
#define TOL 2e-5
#include "operator_cases.inc"
#undef NS
#undef PREC
#undef TOL

#define NS sdf64
#define PREC "double"
#define TOL 1e-9
#include "operator_cases.inc"
#undef NS
#undef PREC
#undef TOL
