// dataset.json of a tsd/1 dataset (FORMAT.md), read through read_dataset like `check` and `evaluate`.
#include "core/tsd.hpp"
#include "fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sb::fuzz::write_input(data, size, "dataset.json");
  sb::fuzz::expect_load_or_input_error([] {
    sb::Warnings warnings;
    const sb::Dataset ds = sb::read_dataset(sb::fuzz::scratch_dir().string(), &warnings);
    (void)ds;
  });
  return 0;
}
