// libFuzzer target: see fuzz/fuzz_inputs.hpp (one_tsd_dataset) for what is fuzzed and the contract.
#include "fuzz/fuzz_inputs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sb::fuzz::one_tsd_dataset(data, size);
  return 0;
}
