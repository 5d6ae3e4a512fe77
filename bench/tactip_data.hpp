#pragma once
// The shipped TacTip set as the benchmarks use it: the import of raw/tactip_shear (about 45 s, made once and kept in
// $TMPDIR/shearbench_bench_tactip), its calibration split with the sensor, and its validation split.
#include <filesystem>
#include <memory>
#include <mutex>

#include "core/base/data_root.hpp"
#include "core/calibration/fit_data.hpp"
#include "core/data/importers.hpp"
#include "core/data/tsd.hpp"

namespace shearbench_bench {

// The import of raw/tactip_shear (made once, kept in $TMPDIR).
inline const sb::Dataset& tactip_dataset() {
  static std::once_flag once;
  static std::unique_ptr<sb::Dataset> ds;
  std::call_once(once, [] {
    const std::string root = sb::resolve_data_root();
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "shearbench_bench_tactip";
    if (!std::filesystem::exists(dir / "dataset.json")) {
      std::filesystem::remove_all(dir);
      sb::import_tactip_shear((std::filesystem::path(root) / "raw" / "tactip_shear").string(), dir.string());
    }
    ds = std::make_unique<sb::Dataset>(sb::read_dataset(dir.string()));
  });
  return *ds;
}

// Its calibration split, loaded once per process.
inline const sb::FitData& tactip_calibration() {
  static std::once_flag once;
  static std::unique_ptr<sb::FitData> data;
  std::call_once(once, [] {
    data = std::make_unique<sb::FitData>(sb::load_calibration_data(tactip_dataset(), sb::resolve_data_root()));
  });
  return *data;
}

// Its validation split (999 samples), loaded once per process.
inline const std::vector<sb::FitSample>& tactip_validation() {
  static std::once_flag once;
  static std::vector<sb::FitSample> samples;
  std::call_once(once, [] {
    const sb::Dataset& ds = tactip_dataset();
    const auto indenters = sb::dataset_indenters(ds, sb::resolve_data_root(), "validation");
    for (const auto& info : ds.samples)
      if (info.split == "validation")
        samples.push_back(sb::to_fit_sample(info, sb::read_sample(ds, info.id), indenters.at(info.indenter)));
  });
  return samples;
}

}  // namespace shearbench_bench
