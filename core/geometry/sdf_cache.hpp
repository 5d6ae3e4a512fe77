#pragma once
// Mesh SDFs built once per process and shared. A workbench fit loads its dataset afresh each time, and every
// load rebuilt the indenter's OpenVDB field (the torus of twin_torus: about 4200 leaves, 10 MB, plus as much
// again in the index grid meshToVolume builds on the way), freed it when the fit ended and left the heap
// fragmented: the hour soak's resident memory stepped up after fits (docs/reliability.md). The
// cache keeps the last few fields, keyed by the mesh's exact vertices and faces and the build options.
#include <cstddef>

#include "core/geometry/sdf.hpp"

namespace sb {

// make_mesh_sdf(mesh, options), or the field an earlier call built for an identical mesh and options.
// Thread-safe; two threads asking at once for a field not yet built may both build it (one is kept).
SdfPtr cached_mesh_sdf(const TriMesh& mesh, const MeshSdfOptions& options);

// How many fields the cache holds (at most kMeshSdfCacheCapacity; the least recently used goes first).
inline constexpr std::size_t kMeshSdfCacheCapacity = 4;
std::size_t mesh_sdf_cache_size();
void clear_mesh_sdf_cache();

}  // namespace sb
