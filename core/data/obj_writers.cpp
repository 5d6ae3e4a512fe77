// Closed meshes written as OBJ text (obj_writers.hpp).
#include "core/data/obj_writers.hpp"

#include <cmath>
#include <sstream>

namespace sb {

std::string sphere_obj(double r, int slices, int stacks) {
  std::ostringstream o;
  o << "# UV sphere, radius " << r << " m, centred at the origin, outward normals (counter-clockwise faces)\n";
  o << "v 0 0 " << r << "\n";
  for (int i = 1; i < stacks; ++i) {
    const double th = M_PI * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double ph = 2 * M_PI * j / slices;
      o << "v " << r * std::sin(th) * std::cos(ph) << " " << r * std::sin(th) * std::sin(ph) << " " << r * std::cos(th)
        << "\n";
    }
  }
  o << "v 0 0 " << -r << "\n";
  auto ring = [&](int i, int j) { return 2 + (i - 1) * slices + (j % slices); };  // 1-based OBJ index
  const int south = 2 + (stacks - 1) * slices;
  for (int j = 0; j < slices; ++j) o << "f 1 " << ring(1, j) << " " << ring(1, j + 1) << "\n";
  for (int i = 1; i < stacks - 1; ++i)
    for (int j = 0; j < slices; ++j) {
      o << "f " << ring(i, j) << " " << ring(i + 1, j) << " " << ring(i + 1, j + 1) << "\n";
      o << "f " << ring(i, j) << " " << ring(i + 1, j + 1) << " " << ring(i, j + 1) << "\n";
    }
  for (int j = 0; j < slices; ++j)
    o << "f " << ring(stacks - 1, j) << " " << south << " " << ring(stacks - 1, j + 1) << "\n";
  return o.str();
}

// A closed box of size (sx, sy, sz) metres occupying z in [0, sz] (contact face at z = 0), outward normals.
std::string box_obj(double sx, double sy, double sz) {
  std::ostringstream o;
  o.precision(17);
  for (int k = 0; k < 8; ++k)
    o << "v " << ((k & 1) ? 0.5 : -0.5) * sx << ' ' << ((k & 2) ? 0.5 : -0.5) * sy << ' ' << ((k & 4) ? sz : 0.0)
      << '\n';
  // Faces as quads split in two, counter-clockwise seen from outside (1-based vertex indices).
  const int quads[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
  for (const auto& q : quads)
    o << "f " << q[0] << ' ' << q[1] << ' ' << q[2] << "\nf " << q[0] << ' ' << q[2] << ' ' << q[3] << '\n';
  return o.str();
}

}  // namespace sb
