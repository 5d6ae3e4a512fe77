#pragma once
// Shared by the libFuzzer targets. The contract every loader is fuzzed against: any byte string either
// loads or throws sb::InputError (which names the file and the place). Anything else (a crash, a
// sanitizer report, a hang, or any other exception escaping, e.g. nlohmann::json::type_error or
// std::out_of_range) is a bug: the uncaught exception aborts and libFuzzer saves the input.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/base/error.hpp"

namespace sb::fuzz {

// A per-process scratch folder in memory (/dev/shm when present): the loaders take paths.
inline const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path base = std::filesystem::exists("/dev/shm") ? "/dev/shm"
                                                                           : std::filesystem::temp_directory_path();
    auto d = base / ("shearbench_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

inline std::string write_input(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const auto path = scratch_dir() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path.string();
}

template <class F>
void expect_load_or_input_error(F&& load) {
  try {
    load();
  } catch (const sb::InputError&) {
    // The documented outcome for bad input.
  }
}

}  // namespace sb::fuzz
