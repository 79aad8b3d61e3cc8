// A LAMMPS data file (atom_style molecular) of closed triangulated "membranes" with dihedrals, for the
// bonded-force tests: regular octahedra of unit circumradius at the given centres, each with its 12
// edges as bonds (type 1, rest length sqrt 2) and its 12 hinges as dihedrals (type 1; atoms a, b, c, d
// with b-c the shared edge, as LAMMPS orders them). Each hinge's normals meet at 70.53 degrees (cos =
// 1/3). A regular octahedron is a stationary point of the dihedral energy (every hinge alike); `jitter`
// moves each vertex off it by a fixed pattern of that size.
#pragma once
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace mesodpd::test {

inline std::string octahedra_data(const std::vector<std::array<double, 3>>& centres, double box, double jitter) {
  const double v[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  // Faces, outward: (x+, y+, z+) and the others by symmetry; each edge once, from the face that runs it
  // upwards, with the third vertices of its two faces.
  const int faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  std::vector<std::array<int, 4>> hinges;
  std::vector<std::array<int, 2>> edges;
  for (int f = 0; f < 8; ++f)
    for (int e = 0; e < 3; ++e) {
      const int b = faces[f][e], c = faces[f][(e + 1) % 3], a = faces[f][(e + 2) % 3];
      if (b > c) continue;
      for (int g = 0; g < 8; ++g)
        for (int k = 0; k < 3; ++k)
          if (faces[g][k] == c && faces[g][(k + 1) % 3] == b) hinges.push_back({a, b, c, faces[g][(k + 2) % 3]});
      edges.push_back({b, c});
    }
  const std::size_t n = centres.size();
  std::string data = fmt::format("octahedra\n{} atoms\n1 atom types\n{} bonds\n1 bond types\n{} dihedrals\n"
                                 "1 dihedral types\n0 {} xlo xhi\n0 {} ylo yhi\n0 {} zlo zhi\n\nAtoms # molecular\n\n",
                                 6 * n, edges.size() * n, hinges.size() * n, box, box, box);
  for (std::size_t m = 0; m < n; ++m)
    for (int k = 0; k < 6; ++k) {
      const int q = static_cast<int>(6 * m) + k;
      data += fmt::format("{} {} 1 {} {} {}\n", q + 1, m + 1, centres[m][0] + v[k][0] + jitter * std::sin(1.7 * q),
                          centres[m][1] + v[k][1] + jitter * std::cos(2.3 * q),
                          centres[m][2] + v[k][2] + jitter * std::sin(0.9 * q + 1));
    }
  data += "\nBonds\n\n";
  for (std::size_t m = 0, id = 1; m < n; ++m)
    for (const auto& e : edges) data += fmt::format("{} 1 {} {}\n", id++, 6 * m + e[0] + 1, 6 * m + e[1] + 1);
  data += "\nDihedrals\n\n";
  for (std::size_t m = 0, id = 1; m < n; ++m)
    for (const auto& h : hinges)
      data += fmt::format("{} 1 {} {} {} {}\n", id++, 6 * m + h[0] + 1, 6 * m + h[1] + 1, 6 * m + h[2] + 1,
                          6 * m + h[3] + 1);
  return data;
}

}  // namespace mesodpd::test
