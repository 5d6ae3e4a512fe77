// core/geometry/sdf_cache: identical mesh and options give the one field built first; anything else builds anew;
// the least recently used field goes when the cache is full.
#include <catch2/catch.hpp>

#include <vector>

#include "core/geometry/indenter.hpp"
#include "core/geometry/sdf_cache.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_sdf_cache {

using sb::Vec3;

namespace {

sb::MeshSdfOptions coarse() {
  sb::MeshSdfOptions o;
  o.voxel_size = 1e-3;  // a 10 mm box at 1 mm voxels builds in milliseconds
  o.band_width = 3e-3;
  return o;
}

}  // namespace

TEST_CASE("mesh SDF cache: the same mesh and options share one field, anything else builds its own",
          "[geometry][sdf][cache]") {
  sb::clear_mesh_sdf_cache();
  const sb::TriMesh box = sb::make_box_mesh(Vec3(0.01, 0.01, 0.01));
  const sb::SdfPtr first = sb::cached_mesh_sdf(box, coarse());
  CHECK(sb::cached_mesh_sdf(box, coarse()) == first);
  CHECK(sb::mesh_sdf_cache_size() == 1);
  // The field is the one make_mesh_sdf builds: 3 mm along x from the centre is 2 mm inside the face x = 5 mm
  // (inside the 3 mm band; negative inside).
  constexpr double kVoxelInterpolation = 1e-4;  // m: trilinear sampling of an exact distance at 1 mm voxels
  CHECK(first->value(Vec3(0.003, 0, 0)) == Approx(-0.002).margin(kVoxelInterpolation));

  sb::MeshSdfOptions finer = coarse();
  finer.voxel_size = 0.5e-3;
  CHECK(sb::cached_mesh_sdf(box, finer) != first);

  sb::TriMesh moved = box;
  moved.vertices[0].x() += 1e-6;  // one vertex a micrometre off is another mesh
  CHECK(sb::cached_mesh_sdf(moved, coarse()) != first);
  CHECK(sb::mesh_sdf_cache_size() == 3);
  sb::clear_mesh_sdf_cache();
}

TEST_CASE("mesh SDF cache: holds at most its capacity, dropping the least recently used", "[geometry][sdf][cache]") {
  sb::clear_mesh_sdf_cache();
  std::vector<sb::TriMesh> boxes;
  for (std::size_t i = 0; i <= sb::kMeshSdfCacheCapacity; ++i)
    boxes.push_back(sb::make_box_mesh(Vec3(0.01 + 0.001 * static_cast<double>(i), 0.01, 0.01)));
  std::vector<sb::SdfPtr> fields;
  for (std::size_t i = 0; i < sb::kMeshSdfCacheCapacity; ++i) fields.push_back(sb::cached_mesh_sdf(boxes[i], coarse()));
  // Touch box 0, then add one more: box 1 (now the least recently used) goes, box 0 stays.
  CHECK(sb::cached_mesh_sdf(boxes[0], coarse()) == fields[0]);
  sb::cached_mesh_sdf(boxes.back(), coarse());
  CHECK(sb::mesh_sdf_cache_size() == sb::kMeshSdfCacheCapacity);
  CHECK(sb::cached_mesh_sdf(boxes[0], coarse()) == fields[0]);
  CHECK(sb::cached_mesh_sdf(boxes[1], coarse()) != fields[1]);  // rebuilt (the old one lives on in `fields`)
  sb::clear_mesh_sdf_cache();
}

}  // namespace test_sdf_cache
