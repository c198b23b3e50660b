// lieservo_bench's main(): Google Benchmark's flags with the programs' exit statuses (bench_main.hpp).
#include "bench_main.hpp"

int main(int argc, char** argv) { return lieservo::bench::runBenchmarks(argc, argv, "the groups' and the estimation's operations, one benchmark each"); }
