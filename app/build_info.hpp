#pragma once
// What `shearbench --version` reports besides the version number: the commit this executable was built
// from (`git describe --always --dirty` at build time, "unknown" outside a git checkout). The definition
// is generated into the build folder by cmake/build_info.cmake.

namespace sb::app {

const char* build_commit();

}  // namespace sb::app
