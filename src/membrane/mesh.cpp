// Mesh generation (geodesic sphere, red cell), OFF input and the closed-surface checks.
#include "membrane/mesh.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

namespace mesodpd::membrane {

namespace {

// The icosahedron: the 12 points (0, +-1, +-g), (+-1, +-g, 0), (+-g, 0, +-1), g the golden ratio, and
// its 20 faces, found as the triples of mutually adjacent points (distance 2), oriented outwards.
void icosahedron(std::vector<Vec3>& v, std::vector<std::array<std::uint32_t, 3>>& faces) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  v.clear();
  for (int s1 : {-1, 1})
    for (int s2 : {-1, 1}) {
      v.push_back({0, s1 * 1.0, s2 * g});
      v.push_back({s1 * 1.0, s2 * g, 0});
      v.push_back({s1 * g, 0, s2 * 1.0});
    }
  auto adjacent = [&](std::uint32_t i, std::uint32_t j) { return std::abs(norm(v[i] - v[j]) - 2.0) < 1e-9; };
  faces.clear();
  const auto n = static_cast<std::uint32_t>(v.size());
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t j = i + 1; j < n; ++j)
      for (std::uint32_t k = j + 1; k < n; ++k)
        if (adjacent(i, j) && adjacent(j, k) && adjacent(i, k)) {
          const Vec3 c = v[i] + v[j] + v[k];
          if (dot(cross(v[j] - v[i], v[k] - v[i]), c) > 0)
            faces.push_back({i, j, k});
          else
            faces.push_back({i, k, j});
        }
}

}  // namespace

int frequency_for(std::size_t vertices) {
  const double n = std::sqrt(std::max(0.0, (static_cast<double>(vertices) - 2.0) / 10.0));
  int best = std::max(1, static_cast<int>(std::floor(n)));
  auto count = [](int f) { return 10.0 * f * f + 2.0; };
  if (std::abs(count(best + 1) - static_cast<double>(vertices)) < std::abs(count(best) - static_cast<double>(vertices)))
    ++best;
  return best;
}

Mesh geodesic_sphere(int frequency, double radius) {
  if (frequency < 1) throw MeshError(fmt::format("geodesic sphere: frequency {} (it must be at least 1)", frequency));
  std::vector<Vec3> corner;
  std::vector<std::array<std::uint32_t, 3>> faces;
  icosahedron(corner, faces);
  const auto n = static_cast<std::uint32_t>(frequency);
  Mesh m;
  // A point of face (A, B, C) with integer barycentric weights (n - i - j, i, j): the same point on a
  // shared edge or corner gets the same key from either face (its nonzero weights by corner index).
  std::map<std::array<std::uint32_t, 6>, std::uint32_t> index;
  auto point = [&](const std::array<std::uint32_t, 3>& f, std::uint32_t i, std::uint32_t j) {
    std::array<std::pair<std::uint32_t, std::uint32_t>, 3> w{{{f[0], n - i - j}, {f[1], i}, {f[2], j}}};
    std::sort(w.begin(), w.end());
    std::array<std::uint32_t, 6> key{};
    std::size_t k = 0;
    for (const auto& [c, weight] : w)
      if (weight > 0) {
        key[k++] = c + 1;
        key[k++] = weight;
      }
    auto [it, fresh] = index.emplace(key, static_cast<std::uint32_t>(m.vertices.size()));
    if (fresh) {
      const double a = static_cast<double>(n - i - j), b = static_cast<double>(i), c = static_cast<double>(j);
      const Vec3 p = (1.0 / n) * (a * corner[f[0]] + b * corner[f[1]] + c * corner[f[2]]);
      m.vertices.push_back((radius / norm(p)) * p);
    }
    return it->second;
  };
  for (const auto& f : faces)
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t j = 0; i + j < n; ++j) {
        m.triangles.push_back({point(f, i, j), point(f, i + 1, j), point(f, i, j + 1)});
        if (i + j + 1 < n) m.triangles.push_back({point(f, i + 1, j), point(f, i + 1, j + 1), point(f, i, j + 1)});
      }
  return m;
}

Mesh red_cell(int frequency, double diameter) {
  constexpr double c0 = 0.0518, c1 = 2.0026, c2 = -4.491;  // Evans & Fung (1972)
  Mesh m = geodesic_sphere(frequency, 1.0);
  for (Vec3& p : m.vertices) {
    const double u = std::min(1.0, p.x * p.x + p.y * p.y);
    p = {0.5 * diameter * p.x, 0.5 * diameter * p.y, p.z * diameter * (c0 + c1 * u / 4.0 + c2 * u * u / 16.0)};
  }
  return m;
}

Mesh read_off(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw MeshError(path + ": cannot be opened");
  std::vector<std::string> lines;  // what each data line holds, comments and blank lines dropped
  std::vector<int> numbers;        // their line numbers
  std::string line;
  for (int k = 1; std::getline(in, line); ++k) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    lines.push_back(line);
    numbers.push_back(k);
  }
  auto fail = [&](std::size_t at, const std::string& why) {
    return MeshError(fmt::format("{}:{}: {}", path, at < numbers.size() ? numbers[at] : 0, why));
  };
  if (lines.empty()) throw MeshError(path + ": empty (an OFF file starts with \"OFF\")");
  std::istringstream head(lines[0]);
  std::string magic;
  head >> magic;
  if (magic != "OFF") throw fail(0, "the first line must be \"OFF\", not \"" + magic + "\"");
  // The counts follow "OFF" on its own line or on the next one.
  std::size_t at = 1;
  std::string rest;
  std::getline(head, rest);
  if (rest.find_first_not_of(" \t\r") == std::string::npos) {
    if (lines.size() < 2) throw fail(0, "expected the vertex, face and edge counts after \"OFF\"");
    rest = lines[1];
    at = 2;
  }
  long long nv = -1, nf = -1;
  std::istringstream counts(rest);
  if (!(counts >> nv >> nf) || nv < 4 || nf < 4)
    throw fail(at - 1, "expected the vertex, face and edge counts (at least 4 vertices and 4 faces)");
  Mesh m;
  for (long long k = 0; k < nv; ++k, ++at) {
    if (at >= lines.size()) throw fail(at, fmt::format("the file ends after {} of {} vertices", k, nv));
    std::istringstream s(lines[at]);
    Vec3 p;
    if (!(s >> p.x >> p.y >> p.z) || !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw fail(at, fmt::format("vertex {}: expected three finite coordinates", k));
    m.vertices.push_back(p);
  }
  for (long long k = 0; k < nf; ++k, ++at) {
    if (at >= lines.size()) throw fail(at, fmt::format("the file ends after {} of {} faces", k, nf));
    std::istringstream s(lines[at]);
    long long count = 0, a = -1, b = -1, c = -1;
    if (!(s >> count) || count != 3)
      throw fail(at, fmt::format("face {}: only triangles are accepted (this face has {} vertices)", k, count));
    if (!(s >> a >> b >> c) || a < 0 || b < 0 || c < 0 || a >= nv || b >= nv || c >= nv)
      throw fail(at, fmt::format("face {}: expected three vertex indices in [0, {})", k, nv));
    m.triangles.push_back({static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(c)});
  }
  check_closed(m, path);
  if (mesh_volume(m, m.vertices) < 0)
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

std::vector<Hinge> check_closed(const Mesh& m, const std::string& source) {
  const auto nv = static_cast<std::uint32_t>(m.vertices.size());
  if (m.triangles.size() < 4) throw MeshError(fmt::format("{}: a closed surface needs at least 4 triangles ({} given)", source, m.triangles.size()));
  // Each directed edge once, with the third vertex of its triangle.
  std::unordered_map<std::uint64_t, std::uint32_t> third;
  auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t{a} << 32) | b; };
  std::vector<std::uint32_t> uses(nv, 0);
  double scale = 0;
  for (const Vec3& p : m.vertices) scale = std::max({scale, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    for (std::uint32_t v : tri)
      if (v >= nv) throw MeshError(fmt::format("{}: triangle {} names vertex {} of {}", source, t, v, nv));
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
      throw MeshError(fmt::format("{}: triangle {} ({} {} {}) repeats a vertex", source, t, tri[0], tri[1], tri[2]));
    const double area = 0.5 * norm(cross(m.vertices[tri[1]] - m.vertices[tri[0]], m.vertices[tri[2]] - m.vertices[tri[0]]));
    if (!(area > 1e-12 * std::max(scale * scale, 1e-300)))
      throw MeshError(fmt::format("{}: triangle {} ({} {} {}) has zero area", source, t, tri[0], tri[1], tri[2]));
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = tri[static_cast<std::size_t>(e)], b = tri[static_cast<std::size_t>((e + 1) % 3)];
      if (!third.emplace(key(a, b), tri[static_cast<std::size_t>((e + 2) % 3)]).second)
        throw MeshError(fmt::format("{}: the edge {}-{} runs the same way in two triangles (one is {}): the mesh is not "
                                    "consistently oriented, or more than two triangles share the edge",
                                    source, a, b, t));
      ++uses[a];
    }
  }
  for (std::uint32_t v = 0; v < nv; ++v)
    if (uses[v] == 0) throw MeshError(fmt::format("{}: vertex {} is in no triangle", source, v));
  std::vector<Hinge> hinges;
  for (const auto& tri : m.triangles)
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t b = tri[static_cast<std::size_t>(e)], c = tri[static_cast<std::size_t>((e + 1) % 3)];
      const auto other = third.find(key(c, b));
      if (other == third.end())
        throw MeshError(fmt::format("{}: the edge {}-{} belongs to one triangle only: the surface is not closed", source, b, c));
      if (b < c) hinges.push_back({tri[static_cast<std::size_t>((e + 2) % 3)], b, c, other->second});
    }
  return hinges;
}

double mesh_area(const Mesh& m, const std::vector<Vec3>& x) {
  double a = 0;
  for (const auto& t : m.triangles) a += 0.5 * norm(cross(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]));
  return a;
}

double mesh_volume(const Mesh& m, const std::vector<Vec3>& x) {
  const Vec3 o = x[0];  // relative to one vertex: the sum does not depend on the origin for a closed mesh
  double v = 0;
  for (const auto& t : m.triangles) v += dot(x[t[0]] - o, cross(x[t[1]] - o, x[t[2]] - o));
  return v / 6.0;
}

}  // namespace mesodpd::membrane
