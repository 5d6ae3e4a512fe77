// `shearbench check --dataset DIR`: validates a tsd/1 dataset (metadata, every sample's CSVs, mesh and
// frame files) and prints a summary, with the rest grid's lattice fit (core/loop/rest_grid_lens.hpp: is it a
// printed lattice, and the lens k1 it shows). Exit 2 when anything is malformed; all errors are listed.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>

#include "app/command.hpp"
#include "core/base/data_root.hpp"
#include "core/data/tactip_sensor.hpp"
#include "core/data/tsd.hpp"
#include "core/loop/rest_grid_lens.hpp"

namespace sb::app {
namespace {

struct CheckArgs {
  std::string dataset;
};

int run_check(const CheckArgs& a, const GlobalOptions& g) {
  const std::string dir = resolve_path(a.dataset, resolve_data_root(g.data_root_flag), "");
  const auto start = std::chrono::steady_clock::now();
  Warnings warnings;
  const Dataset ds = read_dataset(dir, &warnings);  // metadata errors are fatal: nothing else can be read
  std::vector<std::string> errors;
  std::map<std::string, std::map<std::string, int>> counts;  // motion -> split -> samples
  long long frames = 0, marker_values = 0, lost = 0;
  double max_disp = 0;
  int min_frames = 1 << 30, max_frames = 0;
  for (const auto& s : ds.samples) {
    ++counts[s.motion][s.split];
    try {
      const SampleData d = read_sample(ds, s.id, &warnings);
      frames += static_cast<long long>(d.frames());
      min_frames = std::min(min_frames, static_cast<int>(d.frames()));
      max_frames = std::max(max_frames, static_cast<int>(d.frames()));
      for (const auto& frame : d.markers_px)
        for (const Vec2& m : frame) {
          ++marker_values;
          if (!m.allFinite())
            ++lost;
          else
            max_disp = std::max(max_disp, m.norm());
        }
    } catch (const InputError& e) {
      errors.push_back(e.what());
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::printf("dataset %s (%s, tsd/1) in %s\n", ds.name.c_str(), ds.kind.c_str(), dir.c_str());
  std::printf("  sensor %s, image %dx%d px, %.4f mm/px, gel %.2f x %.2f x %.2f mm (%s), %zu markers\n",
              ds.sensor_model.c_str(), ds.camera.width_px, ds.camera.height_px, ds.camera.mm_per_px,
              ds.gel.size_m.x() * 1e3, ds.gel.size_m.y() * 1e3, ds.gel.thickness_m * 1e3, ds.gel.surface.c_str(),
              ds.markers_rest_px.size());
  std::printf("  rest grid: %s\n", describe(rest_grid_lens(ds.camera, ds.markers_rest_px)).c_str());
  // A TacTip import's sensor description: each value, its uncertainty and where it came from.
  if (const auto it = ds.sensor_extra.find("tactip"); it != ds.sensor_extra.end() && it->contains("description")) {
    std::printf("  sensor description (sensor.tactip.description):\n");
    for (const auto& line : tactip_sensor_lines(it->at("description"))) std::printf("    %s\n", line.c_str());
  }
  std::printf("  indenters:");
  for (const auto& [name, ind] : ds.indenters) std::printf(" %s (%s)", name.c_str(), ind.mesh.c_str());
  std::printf("\n  %zu samples:\n", ds.samples.size());
  for (const auto& [motion, splits] : counts) {
    std::printf("    %-9s", motion.c_str());
    for (const auto& [split, n] : splits) std::printf("  %s %d", split.c_str(), n);
    std::printf("\n");
  }
  if (frames > 0) {
    std::printf("  frames: %lld (%d..%d per sample)\n", frames, min_frames, max_frames);
    std::printf("  marker values: %lld, lost (NaN): %.4f%%\n", marker_values,
                100.0 * static_cast<double>(lost) / static_cast<double>(std::max(1LL, marker_values)));
    std::printf("  max displacement: %.3f px (%.4f mm)\n", max_disp, max_disp * ds.camera.mm_per_px);
  }
  std::printf("  read in %.3f s\n", seconds);
  for (const auto& w : warnings.messages) std::printf("  warning: %s\n", w.c_str());
  for (const auto& e : errors) std::cerr << "shearbench: error: " << e << "\n";
  if (!errors.empty()) {
    std::printf("%zu sample(s) with errors\n", errors.size());
    return 2;
  }
  std::printf("ok\n");
  return 0;
}

void add_flags(CLI::App& sub, CheckArgs& a) { add_dataset_flag(sub, a.dataset); }

const Subcommand<CheckArgs> kCheckCommand{"check", "validate a tsd/1 dataset and print a summary (exit 2 on errors)",
                                          40, add_flags, run_check};

}  // namespace
}  // namespace sb::app
