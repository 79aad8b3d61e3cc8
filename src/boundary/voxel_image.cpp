// Voxel image files and the image as a signed-distance shape.
#include "boundary/voxel_image.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

namespace mesodpd {

namespace {

std::string read_all(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("{}: cannot open image file", file));
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Reads the next whitespace-separated token of a PGM header, skipping '#' comments.
std::string pgm_token(const std::string& s, std::size_t& at) {
  for (;;) {
    while (at < s.size() && std::isspace(static_cast<unsigned char>(s[at]))) ++at;
    if (at < s.size() && s[at] == '#') {
      while (at < s.size() && s[at] != '\n') ++at;
      continue;
    }
    break;
  }
  const std::size_t b = at;
  while (at < s.size() && !std::isspace(static_cast<unsigned char>(s[at]))) ++at;
  return s.substr(b, at - b);
}

long pgm_number(const std::string& file, const std::string& s, std::size_t& at, const char* what) {
  const std::string t = pgm_token(s, at);
  char* end = nullptr;
  const long v = t.empty() ? -1 : std::strtol(t.c_str(), &end, 10);
  if (t.empty() || *end != '\0' || v < 0)
    throw ConfigError(fmt::format("{}: bad PGM {} '{}'", file, what, t));
  return v;
}

}  // namespace

VoxelGrid read_pgm(const std::string& file) {
  const std::string s = read_all(file);
  std::size_t at = 0;
  const std::string magic = pgm_token(s, at);
  if (magic != "P2" && magic != "P5")
    throw ConfigError(fmt::format("{}: not a PGM image (expected 'P2' or 'P5' at the start, found '{}')", file, magic));
  const long w = pgm_number(file, s, at, "width"), h = pgm_number(file, s, at, "height");
  const long maxval = pgm_number(file, s, at, "maxval");
  if (w == 0 || h == 0 || maxval == 0 || maxval > 65535 || w * h > (1L << 30))
    throw ConfigError(fmt::format("{}: bad PGM size {} x {} or maxval {}", file, w, h, maxval));
  VoxelGrid g;
  g.n = {static_cast<int>(w), static_cast<int>(h), 1};
  g.solid.assign(static_cast<std::size_t>(w * h), 0);
  // File row r (top first) becomes grid row h - 1 - r (bottom first).
  auto put = [&](long k, long value) {
    const long r = k / w, c = k % w;
    g.solid[g.index(static_cast<int>(c), static_cast<int>(h - 1 - r), 0)] = value != 0 ? 1 : 0;
  };
  if (magic == "P2") {
    for (long k = 0; k < w * h; ++k) {
      const std::string t = pgm_token(s, at);
      if (t.empty())
        throw ConfigError(fmt::format("{}: the image holds {} pixels, {} x {} = {} expected", file, k, w, h, w * h));
      char* end = nullptr;
      const long v = std::strtol(t.c_str(), &end, 10);
      if (*end != '\0' || v < 0 || v > maxval)
        throw ConfigError(fmt::format("{}: pixel {} has value '{}' outside [0, {}]", file, k, t, maxval));
      put(k, v);
    }
    if (!pgm_token(s, at).empty())
      throw ConfigError(fmt::format("{}: more than the {} x {} pixels of the header", file, w, h));
  } else {
    ++at;  // the single whitespace after maxval
    const long bytes = maxval > 255 ? 2 : 1;
    if (static_cast<long>(s.size()) - static_cast<long>(at) != w * h * bytes)
      throw ConfigError(fmt::format("{}: {} bytes of pixel data, {} x {} x {} = {} expected", file,
                                    static_cast<long>(s.size()) - static_cast<long>(at), w, h, bytes, w * h * bytes));
    for (long k = 0; k < w * h; ++k) {
      const auto* b = reinterpret_cast<const unsigned char*>(s.data() + at + static_cast<std::size_t>(k * bytes));
      put(k, bytes == 2 ? (b[0] << 8 | b[1]) : b[0]);
    }
  }
  return g;
}

VoxelGrid read_voxels(const std::string& file) {
  const std::string s = read_all(file);
  std::istringstream in(s);
  std::string line, word;
  auto header = [&](const char* expect) {
    if (!std::getline(in, line)) throw ConfigError(fmt::format("{}: header ends before '{}'", file, expect));
    std::istringstream l(line);
    l >> word;
    if (word != expect)
      throw ConfigError(fmt::format("{}: expected a '{}' line in the MESODPD-VOXELS header, found '{}'", file, expect, line));
    return std::string(std::istreambuf_iterator<char>(l), std::istreambuf_iterator<char>());
  };
  {
    std::istringstream l(header("MESODPD-VOXELS"));
    int version = 0;
    if (!(l >> version) || version != 1)
      throw ConfigError(fmt::format("{}: unsupported MESODPD-VOXELS version (1 expected)", file));
  }
  VoxelGrid g;
  {
    std::istringstream l(header("size"));
    long n[3] = {0, 0, 0};
    if (!(l >> n[0] >> n[1] >> n[2]) || n[0] <= 0 || n[1] <= 0 || n[2] <= 0 || n[0] * n[1] * n[2] > (1L << 31))
      throw ConfigError(fmt::format("{}: 'size' needs three positive integers NX NY NZ", file));
    g.n = {static_cast<int>(n[0]), static_cast<int>(n[1]), static_cast<int>(n[2])};
  }
  std::string encoding;
  {
    std::istringstream l(header("encoding"));
    l >> encoding;
    if (encoding != "ascii" && encoding != "binary")
      throw ConfigError(fmt::format("{}: encoding '{}' is not 'ascii' or 'binary'", file, encoding));
  }
  header("data");
  const std::size_t count = static_cast<std::size_t>(g.n[0]) * static_cast<std::size_t>(g.n[1]) * static_cast<std::size_t>(g.n[2]);
  g.solid.assign(count, 0);
  std::size_t at = static_cast<std::size_t>(in.tellg());
  if (in.tellg() < 0) at = s.size();
  if (encoding == "binary") {
    if (s.size() - at != count)
      throw ConfigError(fmt::format("{}: {} bytes of cell data, {} x {} x {} = {} expected", file, s.size() - at,
                                    g.n[0], g.n[1], g.n[2], count));
    for (std::size_t k = 0; k < count; ++k) {
      const unsigned char v = static_cast<unsigned char>(s[at + k]);
      if (v > 1) throw ConfigError(fmt::format("{}: cell {} has byte value {}, 0 or 1 expected", file, k, v));
      g.solid[k] = v;
    }
  } else {
    std::size_t k = 0;
    for (; at < s.size(); ++at) {
      const char c = s[at];
      if (std::isspace(static_cast<unsigned char>(c))) continue;
      if (c != '0' && c != '1') throw ConfigError(fmt::format("{}: cell {} is '{}', 0 or 1 expected", file, k, c));
      if (k == count) throw ConfigError(fmt::format("{}: more than the {} cells of 'size'", file, count));
      g.solid[k++] = static_cast<std::uint8_t>(c - '0');
    }
    if (k != count)
      throw ConfigError(fmt::format("{}: {} cells, {} x {} x {} = {} expected", file, k, g.n[0], g.n[1], g.n[2], count));
  }
  return g;
}

VoxelGrid load_image(const ShapeSpec& spec, const Box& box, const std::string& key) {
  const std::string& file = spec.file;
  const bool pgm = file.size() >= 4 && (file.substr(file.size() - 4) == ".pgm" || file.substr(file.size() - 4) == ".PGM");
  VoxelGrid g;
  if (pgm) {
    const VoxelGrid img = read_pgm(file);
    // Columns along the first axis other than the extrusion axis, rows along the second.
    const int a0 = spec.axis == 0 ? 1 : 0, a1 = spec.axis == 2 ? 1 : 2;
    g.n = {1, 1, 1};
    g.n[static_cast<std::size_t>(a0)] = img.n[0];
    g.n[static_cast<std::size_t>(a1)] = img.n[1];
    g.solid.assign(img.solid.size(), 0);
    for (int r = 0; r < img.n[1]; ++r)
      for (int c = 0; c < img.n[0]; ++c) {
        int ijk[3] = {0, 0, 0};
        ijk[a0] = c;
        ijk[a1] = r;
        g.solid[g.index(ijk[0], ijk[1], ijk[2])] = img.solid[img.index(c, r, 0)];
      }
  } else {
    g = read_voxels(file);
  }
  if (spec.invert)
    for (auto& v : g.solid) v = static_cast<std::uint8_t>(1 - v);
  for (int d = 0; d < 3; ++d) {
    if (pgm && d == spec.axis) continue;
    const double extent = g.n[static_cast<std::size_t>(d)] * spec.voxel_size;
    if (std::abs(extent - box.length(d)) > 1e-6 * box.length(d))
      throw ConfigError(fmt::format("{}.file: {} has {} cells along {}, which at {}.voxel_size = {} span {}, but "
                                    "system.box is {} long there; the image must cover the box exactly",
                                    key, file, g.n[static_cast<std::size_t>(d)], "xyz"[d], key, spec.voxel_size, extent,
                                    box.length(d)));
  }
  return g;
}

namespace {

constexpr double kFar = 1e30;

// Squared distance transform of one line (Felzenszwalb and Huttenlocher): out[q] = min_p (h^2 (q - p)^2
// + f[p]). On a periodic axis the line is taken three times over and the middle copy kept.
void distance_line(const std::vector<double>& f, double h, bool periodic, std::vector<double>& out) {
  const int n0 = static_cast<int>(f.size());
  const int reps = periodic && n0 > 1 ? 3 : 1;
  const int n = n0 * reps;
  std::vector<double> g(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) g[static_cast<std::size_t>(k)] = f[static_cast<std::size_t>(k % n0)];
  std::vector<int> v(static_cast<std::size_t>(n));
  std::vector<double> z(static_cast<std::size_t>(n) + 1);
  const double h2 = h * h;
  auto cross = [&](int q, int p) {
    return ((g[static_cast<std::size_t>(q)] + h2 * q * q) - (g[static_cast<std::size_t>(p)] + h2 * p * p)) /
           (2.0 * h2 * (q - p));
  };
  // Lower envelope of the parabolas of the finite entries (the features); z[0] = -far ends the search.
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (g[static_cast<std::size_t>(q)] >= kFar) continue;
    if (k < 0) {
      k = 0;
      v[0] = q;
      z[0] = -kFar;
      z[1] = kFar;
      continue;
    }
    double s = cross(q, v[static_cast<std::size_t>(k)]);
    while (s <= z[static_cast<std::size_t>(k)]) {
      --k;
      s = cross(q, v[static_cast<std::size_t>(k)]);
    }
    ++k;
    v[static_cast<std::size_t>(k)] = q;
    z[static_cast<std::size_t>(k)] = s;
    z[static_cast<std::size_t>(k) + 1] = kFar;
  }
  out.assign(static_cast<std::size_t>(n0), kFar);
  if (k < 0) return;  // no feature on this line
  k = 0;
  const int first = (reps == 3) ? n0 : 0;
  for (int q = 0; q < n; ++q) {
    while (z[static_cast<std::size_t>(k) + 1] < q) ++k;
    if (q < first || q >= first + n0) continue;
    const double d = q - v[static_cast<std::size_t>(k)];
    out[static_cast<std::size_t>(q - first)] = h2 * d * d + g[static_cast<std::size_t>(v[static_cast<std::size_t>(k)])];
  }
}

// Squared Euclidean distance from every cell centre to the nearest centre of a cell with solid == phase.
std::vector<double> distance_to(const VoxelGrid& g, std::uint8_t phase, const std::array<double, 3>& h,
                                const std::array<bool, 3>& periodic) {
  std::vector<double> d(g.solid.size());
  for (std::size_t k = 0; k < d.size(); ++k) d[k] = g.solid[k] == phase ? 0.0 : kFar;
  std::vector<double> line, out;
  for (int axis = 0; axis < 3; ++axis) {
    const int n = g.n[static_cast<std::size_t>(axis)];
    const int o1 = axis == 0 ? 1 : 0, o2 = axis == 2 ? 1 : 2;
    for (int b = 0; b < g.n[static_cast<std::size_t>(o2)]; ++b)
      for (int a = 0; a < g.n[static_cast<std::size_t>(o1)]; ++a) {
        line.resize(static_cast<std::size_t>(n));
        auto at = [&](int q) {
          int ijk[3];
          ijk[axis] = q;
          ijk[o1] = a;
          ijk[o2] = b;
          return g.index(ijk[0], ijk[1], ijk[2]);
        };
        for (int q = 0; q < n; ++q) line[static_cast<std::size_t>(q)] = d[at(q)];
        distance_line(line, h[static_cast<std::size_t>(axis)], periodic[static_cast<std::size_t>(axis)], out);
        for (int q = 0; q < n; ++q) d[at(q)] = std::min(out[static_cast<std::size_t>(q)], kFar);
      }
  }
  return d;
}

}  // namespace

ImageShape::ImageShape(const VoxelGrid& g, const Box& box) : n_(g.n), periodic_(box.periodic) {
  for (int d = 0; d < 3; ++d) h_[static_cast<std::size_t>(d)] = box.length(d) / g.n[static_cast<std::size_t>(d)];
  // Axes with one cell (the extrusion axis of a 2-D image) have no spacing to speak of.
  double hmin = kFar;
  for (int d = 0; d < 3; ++d)
    if (n_[static_cast<std::size_t>(d)] > 1) hmin = std::min(hmin, h_[static_cast<std::size_t>(d)]);
  if (hmin >= kFar) hmin = 1.0;
  // Signed distance at cell centres: the surface lies half a cell from the centres next to it.
  const std::vector<double> to_solid = distance_to(g, 1, h_, periodic_);
  const std::vector<double> to_fluid = distance_to(g, 0, h_, periodic_);
  sdf_.resize(g.solid.size());
  for (std::size_t k = 0; k < g.solid.size(); ++k) {
    if (g.solid[k])
      sdf_[k] = static_cast<float>(to_fluid[k] >= kFar ? -kFar : -(std::sqrt(to_fluid[k]) - 0.5 * hmin));
    else
      sdf_[k] = static_cast<float>(to_solid[k] >= kFar ? kFar : std::sqrt(to_solid[k]) - 0.5 * hmin);
  }
  // Smoothed indicator: a [1 2 1] / 4 filter along each axis, twice (a 5-cell binomial), then central
  // differences.
  std::vector<float> s(g.solid.begin(), g.solid.end());
  auto neighbour = [&](int i, int d, int step) {
    const int n = n_[static_cast<std::size_t>(d)];
    int j = i + step;
    if (j < 0 || j >= n) j = periodic_[static_cast<std::size_t>(d)] ? (j + n) % n : std::clamp(j, 0, n - 1);
    return j;
  };
  auto idx = [&](const int c[3]) { return g.index(c[0], c[1], c[2]); };
  for (int pass = 0; pass < 6; ++pass) {
    const int d = pass % 3;
    if (n_[static_cast<std::size_t>(d)] == 1) continue;
    std::vector<float> t(s.size());
    for (int k = 0; k < n_[2]; ++k)
      for (int j = 0; j < n_[1]; ++j)
        for (int i = 0; i < n_[0]; ++i) {
          int c[3] = {i, j, k}, m[3] = {i, j, k}, p[3] = {i, j, k};
          m[d] = neighbour(c[d], d, -1);
          p[d] = neighbour(c[d], d, +1);
          t[idx(c)] = 0.25f * s[idx(m)] + 0.5f * s[idx(c)] + 0.25f * s[idx(p)];
        }
    s.swap(t);
  }
  for (int d = 0; d < 3; ++d) {
    auto& gd = gradient_[d];
    gd.assign(s.size(), 0.0f);
    if (n_[static_cast<std::size_t>(d)] == 1) continue;
    for (int k = 0; k < n_[2]; ++k)
      for (int j = 0; j < n_[1]; ++j)
        for (int i = 0; i < n_[0]; ++i) {
          int c[3] = {i, j, k}, m[3] = {i, j, k}, p[3] = {i, j, k};
          m[d] = neighbour(c[d], d, -1);
          p[d] = neighbour(c[d], d, +1);
          const double span = (p[d] - m[d] + (p[d] < m[d] ? n_[static_cast<std::size_t>(d)] : 0)) * h_[static_cast<std::size_t>(d)];
          gd[idx(c)] = span > 0 ? static_cast<float>((s[idx(p)] - s[idx(m)]) / span) : 0.0f;
        }
  }
}

double ImageShape::interpolate(const std::vector<float>& f, const Vec3& p) const {
  const double q[3] = {p.x, p.y, p.z};
  int i0[3], i1[3];
  double w[3];
  for (int d = 0; d < 3; ++d) {
    const int n = n_[static_cast<std::size_t>(d)];
    const double u = q[d] / h_[static_cast<std::size_t>(d)] - 0.5;  // in cell-centre units
    const double fl = std::floor(u);
    w[d] = u - fl;
    int a = static_cast<int>(fl), b = a + 1;
    if (periodic_[static_cast<std::size_t>(d)]) {
      a = ((a % n) + n) % n;
      b = ((b % n) + n) % n;
    } else {
      if (a < 0) w[d] = 0;
      if (b > n - 1) w[d] = 0;
      a = std::clamp(a, 0, n - 1);
      b = std::clamp(b, 0, n - 1);
      if (a == b) w[d] = 0;
    }
    i0[d] = a;
    i1[d] = b;
  }
  double v = 0;
  for (int c = 0; c < 8; ++c) {
    const int ii = (c & 1) ? i1[0] : i0[0], jj = (c & 2) ? i1[1] : i0[1], kk = (c & 4) ? i1[2] : i0[2];
    const double wt = ((c & 1) ? w[0] : 1 - w[0]) * ((c & 2) ? w[1] : 1 - w[1]) * ((c & 4) ? w[2] : 1 - w[2]);
    if (wt != 0) v += wt * f[static_cast<std::size_t>((static_cast<std::size_t>(kk) * n_[1] + jj) * n_[0] + ii)];
  }
  return v;
}

double ImageShape::sdf(const Vec3& p) const { return interpolate(sdf_, p); }

Vec3 ImageShape::normal(const Vec3& p) const {
  const Vec3 g{-interpolate(gradient_[0], p), -interpolate(gradient_[1], p), -interpolate(gradient_[2], p)};
  const double l = std::sqrt(dot(g, g));
  if (l > 1e-6) return (1.0 / l) * g;
  return Shape::normal(p);  // far from any interface: the gradient of the distance
}

}  // namespace mesodpd
