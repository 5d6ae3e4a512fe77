// params.json (what `fit` writes and --params / the parameter panel read): one file keyed by model id,
// or flat for one model. Applied to every model's table the way the CLI does.
#include "core/evaluate.hpp"
#include "core/json_read.hpp"
#include "core/model.hpp"
#include "fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = sb::fuzz::write_input(data, size, "params.json");
  sb::fuzz::expect_load_or_input_error([&] {
    const nlohmann::json file = sb::jsonin::load_file(path);
    for (const auto& id : sb::model_ids()) {
      sb::ParamSet params = sb::default_params(id);
      params.update_from_json(sb::params_for_model(file, id, true, path), path);
    }
  });
  return 0;
}
