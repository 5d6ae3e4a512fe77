#include "core/geometry/sdf_cache.hpp"

#include <algorithm>
#include <list>
#include <mutex>

namespace sb {

namespace {

struct Entry {
  TriMesh mesh;  // the exact key: a copy (small beside its field)
  MeshSdfOptions options;
  SdfPtr sdf;
};

bool same_options(const MeshSdfOptions& a, const MeshSdfOptions& b) {
  return a.voxel_size == b.voxel_size && a.band_width == b.band_width && a.allow_open == b.allow_open;
}

bool same_mesh(const TriMesh& a, const TriMesh& b) {
  return a.vertices.size() == b.vertices.size() && a.faces.size() == b.faces.size() &&
         std::equal(a.vertices.begin(), a.vertices.end(), b.vertices.begin()) &&
         std::equal(a.faces.begin(), a.faces.end(), b.faces.begin());
}

struct Cache {
  std::mutex mutex;
  std::list<Entry> entries;  // most recently used first
};

Cache& cache() {
  static Cache c;
  return c;
}

// The entry for (mesh, options) moved to the front, or nullptr. Caller holds the mutex.
SdfPtr find_and_touch(Cache& c, const TriMesh& mesh, const MeshSdfOptions& options) {
  for (auto it = c.entries.begin(); it != c.entries.end(); ++it)
    if (same_options(it->options, options) && same_mesh(it->mesh, mesh)) {
      c.entries.splice(c.entries.begin(), c.entries, it);
      return it->sdf;
    }
  return nullptr;
}

}  // namespace

SdfPtr cached_mesh_sdf(const TriMesh& mesh, const MeshSdfOptions& options) {
  Cache& c = cache();
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    if (SdfPtr hit = find_and_touch(c, mesh, options)) return hit;
  }
  SdfPtr built = make_mesh_sdf(mesh, options);  // seconds for a big mesh: not under the lock
  std::lock_guard<std::mutex> lock(c.mutex);
  if (SdfPtr raced = find_and_touch(c, mesh, options)) return raced;
  c.entries.push_front(Entry{mesh, options, built});
  if (c.entries.size() > kMeshSdfCacheCapacity) c.entries.pop_back();
  return built;
}

std::size_t mesh_sdf_cache_size() {
  std::lock_guard<std::mutex> lock(cache().mutex);
  return cache().entries.size();
}

void clear_mesh_sdf_cache() {
  std::lock_guard<std::mutex> lock(cache().mutex);
  cache().entries.clear();
}

}  // namespace sb
