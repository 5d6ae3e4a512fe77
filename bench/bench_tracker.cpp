// Tracker speed on real 320x240 GelSight Mini frames: detection alone and detection + matching per frame,
// for a clean clip (mini_example.avi) and one with the vendor's red overlay (video_5.avi).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>

#include "core/base/data_root.hpp"
#include "core/tracking/tracker.hpp"

namespace {

std::vector<cv::Mat> load(const std::string& rel) {
  cv::setNumThreads(1);  // the requirement is per core; OpenCV's own threads would blur that
  const char* env = std::getenv("SHEARBENCH_DATA");
  const std::string root = env && *env ? env : sb::resolve_data_root();
  return sb::read_video_frames((std::filesystem::path(root) / rel).string());
}

void BM_Detect(benchmark::State& state, const char* rel) {
  const auto frames = load(rel);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(sb::detect_markers(frames[i++ % frames.size()], {}));
  state.SetItemsProcessed(state.iterations());
}

void BM_Track(benchmark::State& state, const char* rel) {
  const auto frames = load(rel);
  for (auto _ : state) benchmark::DoNotOptimize(sb::track_frames(frames, {}));
  state.SetItemsProcessed(state.iterations() * frames.size());
}

BENCHMARK_CAPTURE(BM_Detect, clean, "raw/gsrobotics_tracking/mini_example.avi")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Detect, overlay, "raw/gsrobotics_tracking/video_5.avi")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Track, clean, "raw/gsrobotics_tracking/mini_example.avi")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Track, overlay, "raw/gsrobotics_tracking/video_5.avi")->Unit(benchmark::kMillisecond);

}  // namespace
