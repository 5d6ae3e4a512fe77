#pragma once
// The checks of a mesh file (OBJ, STL, PLY, OFF) before OpenMesh reads it: the counts the file declares or holds.
#include <string>

namespace sb {

// Counts the file declares or contains, found by a scan independent of OpenMesh (-1: unknown).
struct MeshFileCounts {
  long vertices = -1;
  long faces = -1;
};

// The file's extension in lower case, with its dot (".obj").
std::string mesh_file_extension(const std::string& path);

// Scans the file by its extension `ext` (mesh_file_extension): a truncated or corrupt body, a non-finite vertex, a
// face referring to a vertex the file lacks, or an unknown extension is an InputError naming the file and line.
MeshFileCounts scan_mesh_file(const std::string& path, const std::string& ext);

}  // namespace sb
