// A fuzz target: one input, any bytes. It must return normally or throw std::exception (a
// clean error is the right answer to bad input); a crash, a sanitizer report or a hang is a
// finding. Built two ways (test/fuzz/CMakeLists.txt): with clang's libFuzzer (scripts/fuzz,
// coverage-guided, ASan/UBSan) and, in the ordinary build, with fuzz_driver_main.cpp, which
// replays the seed corpus and then runs a fixed-seed mutation loop (the test suite's short run).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace rnav::fuzz {

/// Run one input through the target; bad input ends in an exception, caught by the caller.
void run_one(const std::uint8_t* data, std::size_t size);

/// A private scratch folder for targets that read files (created once per process).
const std::string& scratch_dir();

/// Write `size` bytes to scratch_dir()/name; returns the path.
std::string write_scratch(const std::string& name, const std::uint8_t* data, std::size_t size);

}  // namespace rnav::fuzz
