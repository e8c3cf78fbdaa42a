// bench_input_tool [seconds]: runs RunInputBench (the app wires the same as `sdfvj bench input`).
#include <cstdlib>

#include "control/control.h"

int main(int argc, char** argv) { return sdfvj::RunInputBench(argc > 1 ? std::atof(argv[1]) : 60.0); }
