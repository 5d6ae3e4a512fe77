// The per-sample CSVs of tsd/1 (poses.csv, markers.csv, forces.csv). The first byte picks the reader, so
// one corpus covers all three; the rest is the file.
#include "core/tsd.hpp"
#include "fuzz/fuzz_common.hpp"

namespace {
constexpr std::size_t kFrames = 64;    // what dataset.json would declare for the sample
constexpr std::size_t kMarkers = 63;   // the 7 x 9 GelSight Mini grid
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int reader = data[0] % 3;
  const char* names[] = {"poses.csv", "markers.csv", "forces.csv"};
  const std::string path = sb::fuzz::write_input(data + 1, size - 1, names[reader]);
  sb::fuzz::expect_load_or_input_error([&] {
    sb::SampleData sample;
    sb::Warnings warnings;
    if (reader == 0) sb::read_poses_csv(path, &sample, &warnings);
    if (reader == 1) sb::read_markers_csv(path, kFrames, kMarkers, &sample);
    if (reader == 2) sb::read_forces_csv(path, kFrames, &sample);
  });
  return 0;
}
