// The mesh loaders (OpenMesh behind our own checks). The first byte picks the extension: OBJ, STL,
// PLY, OFF; the rest is the file. Open meshes are allowed so the fuzzer gets past the hole check.
#include "core/mesh.hpp"
#include "fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const char* names[] = {"mesh.obj", "mesh.stl", "mesh.ply", "mesh.off"};
  const std::uint8_t selector = data[0];
  const std::string path = sb::fuzz::write_input(data + 1, size - 1, names[selector % 4]);
  sb::fuzz::expect_load_or_input_error([&] {
    sb::MeshLoadOptions options;
    options.allow_open = (selector & 4) != 0;
    sb::Warnings warnings;
    const sb::TriMesh mesh = sb::load_mesh(path, options, nullptr, &warnings);
    (void)mesh;
  });
  return 0;
}
