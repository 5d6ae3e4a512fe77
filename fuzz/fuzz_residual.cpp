// libFuzzer target: see fuzz/fuzz_inputs.hpp (one_residual) for what is fuzzed and the contract.
#include "fuzz/fuzz_inputs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sb::fuzz::one_residual(data, size);
  return 0;
}
