#pragma once
// A path in the system's temporary folder that is this process's own: test binaries of two checkouts (or
// a sanitizer build beside a release one) may run at once, and a shared fixed name let one delete the
// other's files mid-test.
#include <unistd.h>

#include <filesystem>
#include <string>

namespace sbtest {

inline std::filesystem::path temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
}

}  // namespace sbtest
