// Scene JSON (scenes/*.json) through load_scene, with a data root that does not exist so data: paths
// fail cleanly instead of loading large meshes.
#include "core/scene.hpp"
#include "fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = sb::fuzz::write_input(data, size, "scene.json");
  sb::fuzz::expect_load_or_input_error([&] {
    const sb::Scene scene = sb::load_scene(path, (sb::fuzz::scratch_dir() / "no_data_root").string());
    (void)scene;
  });
  return 0;
}
