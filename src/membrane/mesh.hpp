// Closed triangulated surfaces for cell membranes (issue "Cell membranes and red blood cells"): the
// geodesic sphere, the Evans-Fung biconcave red-cell shape, meshes read from OFF files, and the checks a
// membrane needs (closed, every edge shared by two triangles of opposite direction, no degenerate
// triangle). The mesh is the cell's topology and its reference (stress-free) shape; the forces are in
// membrane/membrane_forces.hpp.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/vec3.hpp"

namespace mesodpd::membrane {

// Vector helpers the membrane code shares (core's Vec3 has no norm).
inline double norm(Vec3 a) { return std::sqrt(dot(a, a)); }

struct Mesh {
  std::vector<Vec3> vertices;
  // Counter-clockwise seen from outside: the normal (b - a) x (c - a) points out of the enclosed volume.
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// An edge shared by two triangles, for bonds and bending: the edge (b, c), with a the third vertex of
// the triangle (a, b, c) and d that of the triangle (d, c, b), both in the mesh's orientation.
struct Hinge {
  std::uint32_t a = 0, b = 0, c = 0, d = 0;
};

// Why a mesh cannot be a membrane; what() names the source, the triangle or the edge.
struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The geodesic sphere of icosahedral frequency n >= 1: each face of the icosahedron cut into n^2
// triangles and projected onto the sphere, 10 n^2 + 2 vertices, 20 n^2 triangles.
Mesh geodesic_sphere(int frequency, double radius);
// The frequency whose 10 n^2 + 2 vertices come nearest `vertices` (at least 1).
int frequency_for(std::size_t vertices);
// The biconcave resting shape of a human red cell (Evans & Fung, Microvasc. Res. 4, 335 (1972)): with
// rho the distance from the axis (z) and D the diameter,
//   z = +-D sqrt(1 - 4 rho^2/D^2) (c0 + c1 rho^2/D^2 + c2 rho^4/D^4),
//   c0 = 0.0518, c1 = 2.0026, c2 = -4.491 (D = 7.82 um: 0.81 um thick at the centre, 2.5 um at the rim),
// made from the geodesic sphere of that frequency by mapping each unit-sphere point (x, y, z) to
// (D/2 x, D/2 y, z D (c0 + c1 u/4 + c2 u^2/16)), u = x^2 + y^2 (then |z| = sqrt(1 - u)): the sphere's
// triangulation, squeezed onto the cell's surface.
Mesh red_cell(int frequency, double diameter);
// A mesh read from an OFF file (the "OFF" header, vertex and face counts, the vertices, then faces of
// three vertices; comments after '#'); errors name the file and line. The faces must be oriented
// consistently; if they enclose a negative volume every face is reversed.
Mesh read_off(const std::string& path);

// Checks that `m` is a closed, consistently oriented 2-manifold with no degenerate triangle, and
// returns its hinges (one per edge, in order of first appearance). Errors start with `source`.
std::vector<Hinge> check_closed(const Mesh& m, const std::string& source);

// Area, enclosed volume (positive for an outward orientation) and the triangle areas of `x`, a set of
// positions in the mesh's vertex order.
double mesh_area(const Mesh& m, const std::vector<Vec3>& x);
double mesh_volume(const Mesh& m, const std::vector<Vec3>& x);

}  // namespace mesodpd::membrane
