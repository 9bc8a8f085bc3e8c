// The one Catch2 main shared by all unit-test executables (compiled once, object library), with
// the memory settings of the programs that run the effect search (process_memory.hpp).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "common/io/process_memory.hpp"

int main(int argc, char* argv[]) {
  rnav::cli::keep_freed_memory();
  return Catch::Session().run(argc, argv);
}
