#pragma once
// Closed meshes written as OBJ text, for the indenters an importer writes beside its dataset.
#include <string>

namespace sb {

// Writes a closed UV sphere of radius r (metres) centred at the origin, outward normals, as OBJ text.
std::string sphere_obj(double radius_m, int slices = 32, int stacks = 16);
// Writes a closed box of size (sx, sy, sz) metres occupying z in [0, sz] (contact face at z = 0), outward normals,
// as OBJ text.
std::string box_obj(double sx, double sy, double sz);

}  // namespace sb
