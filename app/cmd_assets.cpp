// `shearbench assets`: writes the procedural indenter meshes the scenes use, as OBJ in metres.
#include <filesystem>
#include <iostream>

#include "app/command.hpp"
#include "core/geometry/indenter.hpp"

namespace sb::app {
namespace {

struct Asset {
  const char* name;
  TriMesh (*make)();
};

// Names carry the dimensions in millimetres; the meshes are in metres, centred at the origin.
const Asset kAssets[] = {
    {"sphere_r4", [] { return make_sphere_mesh(4e-3); }},
    {"sphere_r17.5", [] { return make_sphere_mesh(17.5e-3); }},
    {"torus_R6_r1.5", [] { return make_torus_mesh(6e-3, 1.5e-3); }},
    {"cylinder_r4_l40_f0.5", [] { return make_cylinder_mesh(4e-3, 40e-3, 0.5e-3); }},  // the benchmark peg
    {"punch_r3_f0.5", [] { return make_cylinder_mesh(3e-3, 10e-3, 0.5e-3); }},
    {"box_10x10x5", [] { return make_box_mesh(Vec3(10e-3, 10e-3, 5e-3)); }},
};

struct AssetsArgs {
  std::string out = "assets";
};

int run_assets(const AssetsArgs& args, const GlobalOptions& global) {
  const std::string& out_dir = args.out;
  for (const auto& a : kAssets) {
    const TriMesh mesh = a.make();
    const std::string path = (std::filesystem::path(out_dir) / (std::string(a.name) + ".obj")).string();
    save_obj(mesh, path);
    if (!global.quiet)
      std::cout << path << ": " << mesh.vertices.size() << " vertices, " << mesh.faces.size() << " faces\n";
  }
  return 0;
}

void add_flags(CLI::App& sub, AssetsArgs& a) { sub.add_option("--out", a.out, "output directory (default: assets)"); }

const Subcommand<AssetsArgs> kAssetsCommand{
    "assets", "write the procedural indenter meshes (OBJ, metres) the scenes use", 80, add_flags, run_assets};

}  // namespace
}  // namespace sb::app
