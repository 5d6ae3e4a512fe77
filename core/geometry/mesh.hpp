#pragma once
// Triangle meshes: the one in-memory type every module shares (OpenMesh stays inside mesh.cpp).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/base/error.hpp"
#include "core/geometry/pose.hpp"

namespace sb {

struct TriMesh {
  std::vector<Vec3> vertices;          // metres, in the mesh's own frame
  std::vector<Eigen::Vector3i> faces;  // counter-clockwise seen from outside (outward normals)

  bool empty() const { return faces.empty(); }
  double area() const;
  double signed_volume() const;  // > 0 for a closed mesh with outward normals
  Eigen::AlignedBox3d bounds() const;
  TriMesh transformed(const Pose& X) const;  // X_AB applied to a mesh given in B gives the mesh in A
};

// What validation found. `closed` means every edge is shared by exactly two faces.
struct MeshReport {
  std::size_t boundary_edges = 0;      // edges with one face: holes
  std::size_t nonmanifold_edges = 0;   // edges with three or more faces
  std::size_t inconsistent_edges = 0;  // edges traversed in the same direction by both faces
  std::size_t degenerate_faces = 0;    // zero area or repeated vertex
  std::size_t unreferenced_vertices = 0;
  int euler_characteristic = 0;
  bool closed() const { return boundary_edges == 0 && nonmanifold_edges == 0; }
  bool consistently_oriented() const { return inconsistent_edges == 0; }
  std::string summary() const;
};

struct MeshLoadOptions {
  double scale = 1.0;       // multiply file units by this to get metres (explicit, never guessed)
  bool allow_open = false;  // best-effort: accept meshes with holes (SDF sign then approximate)
};

// Loads OBJ, STL (ASCII or binary), PLY or OFF. Throws InputError naming the file for: a missing or
// unreadable file, an unknown extension, a truncated or empty mesh, a non-finite vertex, and (unless
// allow_open) a mesh with holes. Non-fatal problems (non-manifold edges, degenerate faces, inward
// orientation that was flipped) go into `warnings`.
TriMesh load_mesh(const std::string& path, const MeshLoadOptions& options, MeshReport* report = nullptr,
                  Warnings* warnings = nullptr);

MeshReport validate_mesh(const TriMesh& mesh);

// Writes OBJ atomically (temporary file, then rename).
void save_obj(const TriMesh& mesh, const std::string& path);

}  // namespace sb
