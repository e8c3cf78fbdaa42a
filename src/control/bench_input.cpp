namespace sdfvj { int RunInputBench(double) { return 0; } }
