#pragma once
// One input of each fuzz target, shared by the libFuzzer targets (fuzz/fuzz_*.cpp) and the regression
// test (tests/test_fuzz_regressions.cpp), which replays every input a fuzzer ever crashed on
// (tests/data/fuzz/<target>/). Each either loads or throws sb::InputError, which is swallowed here;
// anything else escapes (and is a bug).
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/calibration/evaluate.hpp"
#include "core/data/json_read.hpp"
#include "core/data/scene.hpp"
#include "core/data/tsd.hpp"
#include "core/geometry/mesh.hpp"
#include "core/loop/residual_view.hpp"
#include "core/models/model.hpp"
#include "core/workbench/session_file.hpp"
#include "fuzz/fuzz_common.hpp"

namespace sb::fuzz {

// dataset.json of a tsd/1 dataset (FORMAT.md), through read_dataset like `check` and `evaluate`.
inline void one_tsd_dataset(const std::uint8_t* data, std::size_t size) {
  write_input(data, size, "dataset.json");
  expect_load_or_input_error([] {
    Warnings warnings;
    (void)read_dataset(scratch_dir().string(), &warnings);
  });
}

// poses.csv / markers.csv / forces.csv: the first byte picks the reader, the rest is the file.
inline void one_tsd_csv(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return;
  constexpr std::size_t kFrames = 64;   // what dataset.json would declare for the sample
  constexpr std::size_t kMarkers = 63;  // the 7 x 9 GelSight Mini grid
  const int reader = data[0] % 3;
  const char* names[] = {"poses.csv", "markers.csv", "forces.csv"};
  const std::string path = write_input(data + 1, size - 1, names[reader]);
  expect_load_or_input_error([&] {
    SampleData sample;
    Warnings warnings;
    if (reader == 0) read_poses_csv(path, &sample, &warnings);
    if (reader == 1) read_markers_csv(path, kFrames, kMarkers, &sample);
    if (reader == 2) read_forces_csv(path, kFrames, &sample);
  });
}

// Meshes: the first byte picks OBJ, STL, PLY or OFF (bit 2: allow open meshes); the rest is the file.
inline void one_mesh(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return;
  const char* names[] = {"mesh.obj", "mesh.stl", "mesh.ply", "mesh.off"};
  const std::uint8_t selector = data[0];
  const std::string path = write_input(data + 1, size - 1, names[selector % 4]);
  expect_load_or_input_error([&] {
    MeshLoadOptions options;
    options.allow_open = (selector & 4) != 0;
    Warnings warnings;
    (void)load_mesh(path, options, nullptr, &warnings);
  });
}

// Scene JSON through load_scene; the data root does not exist, so data: paths fail cleanly.
inline void one_scene(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_input(data, size, "scene.json");
  expect_load_or_input_error([&] { (void)load_scene(path, (scratch_dir() / "no_data_root").string()); });
}

// params.json applied to every model's table the way the CLI does (keyed by model id, or flat).
inline void one_params(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_input(data, size, "params.json");
  expect_load_or_input_error([&] {
    const nlohmann::json file = jsonin::load_file(path);
    for (const auto& id : model_ids()) {
      ParamSet params = default_params(id);
      params.update_from_json(params_for_model(file, id, true, path), path);
    }
  });
}

// The workbench session file.
inline void one_session(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_input(data, size, "session.json");
  expect_load_or_input_error([&] { (void)load_session_file(path); });
}

// A residual analysis as the workbench reads it (shearbench residual --json).
inline void one_residual(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_input(data, size, "residual.json");
  expect_load_or_input_error([&] { (void)load_residual_summary(path); });
}

}  // namespace sb::fuzz
