// Implementation of read_lammps_data: a line-oriented parser for the LAMMPS data file layout
// (title line, header of "count keyword" lines, then sections each introduced by a keyword line).
#include "io/lammps_data_reader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

#include "mesodpd/config_error.hpp"

namespace mesodpd {
namespace {

struct Line {
  std::size_t number = 0;           // 1-based line number in the file
  std::vector<std::string> tokens;  // whitespace-separated words before any '#'
  std::string comment;              // text after the first '#', trimmed
};

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return std::string(s.substr(b, e - b + 1));
}

Line split(std::size_t number, const std::string& raw) {
  Line line;
  line.number = number;
  const auto hash = raw.find('#');
  const std::string_view body = std::string_view(raw).substr(0, hash);
  if (hash != std::string::npos) line.comment = trim(std::string_view(raw).substr(hash + 1));
  std::size_t pos = 0;
  while (pos < body.size()) {
    while (pos < body.size() && std::isspace(static_cast<unsigned char>(body[pos]))) ++pos;
    std::size_t end = pos;
    while (end < body.size() && !std::isspace(static_cast<unsigned char>(body[end]))) ++end;
    if (end > pos) line.tokens.emplace_back(body.substr(pos, end - pos));
    pos = end;
  }
  return line;
}

// A section keyword line starts with a letter; data and header lines start with a number.
bool is_section_line(const Line& line) {
  return !line.tokens.empty() && std::isalpha(static_cast<unsigned char>(line.tokens[0][0]));
}

std::string join(const std::vector<std::string>& tokens, std::size_t first) {
  std::string out;
  for (std::size_t k = first; k < tokens.size(); ++k) {
    if (!out.empty()) out += ' ';
    out += tokens[k];
  }
  return out;
}

class Parser {
 public:
  explicit Parser(const std::filesystem::path& path) : path_(path) {}

  [[noreturn]] void fail(const std::string& message) const {
    throw ConfigError("LAMMPS data file '" + path_.string() + "': " + message);
  }
  [[noreturn]] void fail(const Line& line, const std::string& message) const {
    throw ConfigError("LAMMPS data file '" + path_.string() + "', line " + std::to_string(line.number) +
                      ": " + message);
  }

  double real(const Line& line, std::size_t k, const char* what) const {
    std::string_view s = line.tokens[k];
    if (!s.empty() && s[0] == '+') s.remove_prefix(1);  // from_chars rejects an explicit '+'
    double v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) {
      fail(line,
           std::string("cannot read ") + what + " from '" + line.tokens[k] + "' (expected a finite number)");
    }
    return v;
  }

  std::int64_t integer(const Line& line, std::size_t k, const char* what, std::int64_t min,
                       std::int64_t max) const {
    std::string_view s = line.tokens[k];
    if (!s.empty() && s[0] == '+') s.remove_prefix(1);
    std::int64_t v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size()) {
      fail(line, std::string("cannot read ") + what + " from '" + line.tokens[k] + "' (expected an integer)");
    }
    if (v < min || v > max) {
      fail(line, std::string(what) + " " + std::to_string(v) + " is out of range [" + std::to_string(min) +
                     ", " + std::to_string(max) + "]");
    }
    return v;
  }

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

struct Section {
  Line header;
  std::vector<Line> lines;
};

}  // namespace

LammpsData read_lammps_data(const std::filesystem::path& path, int tdpd_concentrations) {
  Parser p(path);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) p.fail("file does not exist");
  std::ifstream in(path);
  if (!in) p.fail("cannot open file for reading");

  // Gather header lines and sections. Line 1 is a free-form title, always ignored.
  std::vector<Line> header;
  std::vector<Section> sections;
  std::string raw;
  std::size_t number = 0;
  while (std::getline(in, raw)) {
    ++number;
    if (number == 1) continue;
    Line line = split(number, raw);
    if (line.tokens.empty()) continue;
    if (is_section_line(line)) {
      sections.push_back(Section{std::move(line), {}});
    } else if (sections.empty()) {
      header.push_back(std::move(line));
    } else {
      sections.back().lines.push_back(std::move(line));
    }
  }
  if (in.bad()) p.fail("read error");

  LammpsData data;
  std::optional<std::int64_t> n_atoms, n_types;
  std::int64_t n_bonds = 0, n_angles = 0, n_dihedrals = 0;
  std::array<bool, 3> have_bounds{};
  constexpr std::int64_t kMaxCount = std::numeric_limits<std::uint32_t>::max();
  for (const Line& line : header) {
    const auto& t = line.tokens;
    if (t.size() == 2 && t[1] == "atoms") {
      n_atoms = p.integer(line, 0, "atom count", 0, kMaxCount);
    } else if (t.size() == 3 && t[1] == "atom" && t[2] == "types") {
      n_types = p.integer(line, 0, "atom type count", 1, std::numeric_limits<int>::max());
    } else if (t.size() == 4 && (t[2] == "xlo" || t[2] == "ylo" || t[2] == "zlo") && t[3][0] == t[2][0] &&
               t[3].substr(1) == "hi") {
      const int d = t[2][0] - 'x';
      data.lo[d] = p.real(line, 0, "lower box bound");
      data.hi[d] = p.real(line, 1, "upper box bound");
      if (!(data.hi[d] > data.lo[d])) p.fail(line, t[3] + " must be greater than " + t[2]);
      have_bounds[d] = true;
    } else if (t.size() == 6 && t[3] == "xy" && t[4] == "xz" && t[5] == "yz") {
      // A triclinic box with all tilts zero is the orthorhombic box, so only real tilts are refused.
      for (std::size_t k = 0; k < 3; ++k) {
        if (p.real(line, k, "tilt factor") != 0.0) {
          p.fail(line, "triclinic box (nonzero xy xz yz tilt) is not supported: orthorhombic only");
        }
      }
    } else if (t.size() >= 2 && std::isdigit(static_cast<unsigned char>(t[0][0]))) {
      // Counts of things atom_style atomic does not have are fine when zero (write_data emits some).
      static const char* const kZeroOnly[] = {"impropers", "improper types", "ellipsoids",
                                              "lines",     "triangles",      "bodies"};
      // Hints for LAMMPS's memory, meaningless here.
      static const char* const kIgnored[] = {"extra bond per atom", "extra angle per atom", "extra dihedral per atom",
                                             "extra improper per atom", "extra special per atom"};
      const std::string keyword = join(t, 1);
      if (std::find(std::begin(kIgnored), std::end(kIgnored), keyword) != std::end(kIgnored)) {
        p.integer(line, 0, keyword.c_str(), 0, std::numeric_limits<std::int64_t>::max());
        continue;
      }
      if (keyword == "bonds" || keyword == "angles" || keyword == "dihedrals") {
        (keyword == "bonds" ? n_bonds : keyword == "angles" ? n_angles : n_dihedrals) =
            p.integer(line, 0, keyword.c_str(), 0, kMaxCount);
        continue;
      }
      if (keyword == "bond types" || keyword == "angle types" || keyword == "dihedral types") {
        (keyword == "bond types" ? data.n_bond_types
                                 : keyword == "angle types" ? data.n_angle_types : data.n_dihedral_types) =
            static_cast<int>(p.integer(line, 0, keyword.c_str(), 0, std::numeric_limits<int>::max()));
        continue;
      }
      if (std::find(std::begin(kZeroOnly), std::end(kZeroOnly), keyword) == std::end(kZeroOnly)) {
        p.fail(line, "unknown header line '" + join(t, 0) + "'");
      }
      if (p.integer(line, 0, keyword.c_str(), 0, std::numeric_limits<std::int64_t>::max()) != 0) {
        p.fail(line, "'" + keyword + "' is not supported: bonds, angles and dihedrals are the bonded terms mesodpd reads");
      }
    } else {
      p.fail(line, "unknown header line '" + join(t, 0) + "'");
    }
  }
  if (!n_atoms) p.fail("header has no 'atoms' count");
  if (!n_types) p.fail("header has no 'atom types' count");
  for (int d = 0; d < 3; ++d) {
    if (!have_bounds[d]) {
      const char axis = static_cast<char>('x' + d);
      p.fail(std::string("header has no '") + axis + "lo " + axis + "hi' box bounds");
    }
  }
  data.n_types = static_cast<int>(*n_types);

  const Section* atoms = nullptr;
  const Section* masses = nullptr;
  const Section* velocities = nullptr;
  const Section* bonds = nullptr;
  const Section* angles = nullptr;
  const Section* dihedrals = nullptr;
  for (const Section& s : sections) {
    const std::string name = join(s.header.tokens, 0);
    const Section** slot = nullptr;
    if (name == "Atoms") {
      slot = &atoms;
      static const char* const kStyles[] = {"atomic", "bond", "angle", "molecular", "full", "edpd", "tdpd"};
      if (!s.header.comment.empty() &&
          std::find(std::begin(kStyles), std::end(kStyles), s.header.comment) == std::end(kStyles)) {
        p.fail(s.header, "atom style '" + s.header.comment +
                             "' is not supported: atomic, bond, angle, molecular, full (without charges), edpd or tdpd");
      }
      if (s.header.comment == "tdpd" && tdpd_concentrations <= 0)
        p.fail(s.header, "atom style 'tdpd' is read only by a run with pair.style = \"tdpd\" (its [tdpd] solutes "
                         "give the number of cc columns)");
    } else if (name == "Bonds") {
      slot = &bonds;
    } else if (name == "Angles") {
      slot = &angles;
    } else if (name == "Dihedrals") {
      slot = &dihedrals;
    } else if (name == "Masses") {
      slot = &masses;
    } else if (name == "Velocities") {
      slot = &velocities;
    } else if (name.size() > 7 && name.ends_with(" Coeffs")) {
      continue;  // interaction parameters come from the mesodpd configuration, not the data file
    } else {
      p.fail(s.header, "section '" + name + "' is not supported (Masses, Atoms, Velocities, Bonds, Angles, "
                                            "Dihedrals and ... Coeffs are read)");
    }
    if (*slot != nullptr) {
      p.fail(s.header,
             "second '" + name + "' section (first at line " + std::to_string((*slot)->header.number) + ")");
    }
    *slot = &s;
  }

  if (masses != nullptr) {
    data.masses.assign(static_cast<std::size_t>(data.n_types), 0.0);
    std::vector<std::size_t> seen_at(data.masses.size(), 0);
    for (const Line& line : masses->lines) {
      if (line.tokens.size() != 2) p.fail(line, "expected 'type mass' in Masses section");
      const auto type = p.integer(line, 0, "atom type", 1, data.n_types);
      const double mass = p.real(line, 1, "mass");
      if (!(mass > 0)) p.fail(line, "mass of type " + std::to_string(type) + " must be positive");
      auto& seen = seen_at[static_cast<std::size_t>(type - 1)];
      if (seen != 0) {
        p.fail(line, "mass of type " + std::to_string(type) + " given twice (first at line " +
                         std::to_string(seen) + ")");
      }
      seen = line.number;
      data.masses[static_cast<std::size_t>(type - 1)] = mass;
    }
    for (std::size_t t = 0; t < seen_at.size(); ++t) {
      if (seen_at[t] == 0)
        p.fail(masses->header, "Masses section has no mass for atom type " + std::to_string(t + 1));
    }
  }

  if (atoms == nullptr) {
    if (*n_atoms > 0)
      p.fail("no Atoms section, but the header declares " + std::to_string(*n_atoms) + " atoms");
  } else {
    if (static_cast<std::int64_t>(atoms->lines.size()) != *n_atoms) {
      p.fail(atoms->header, "Atoms section has " + std::to_string(atoms->lines.size()) +
                                " lines, but the header declares " + std::to_string(*n_atoms) + " atoms");
    }
    data.atoms.reserve(atoms->lines.size());
    std::unordered_map<std::uint32_t, std::size_t> line_of_id;
    // The style: named after "Atoms", or known from the column count (5/8 atomic, 6/9 molecular, 7/10 full).
    std::string style = atoms->header.comment;
    if (style == "bond" || style == "angle") style = "molecular";
    if (style.empty() && !atoms->lines.empty()) {
      const std::size_t c = atoms->lines.front().tokens.size();
      style = (c == 5 || c == 8) ? "atomic" : (c == 6 || c == 9) ? "molecular" : (c == 7 || c == 10) ? "full" : "";
      if (style.empty())
        p.fail(atoms->lines.front(), "cannot tell the atom style from " + std::to_string(c) +
                                         " columns; name it after 'Atoms' (e.g. 'Atoms # molecular')");
    }
    data.style = style;
    const bool edpd = style == "edpd", tdpd = style == "tdpd";
    if (tdpd) data.concentrations = tdpd_concentrations;
    const std::size_t base = style == "atomic"      ? 5
                             : style == "molecular" ? 6
                             : edpd                 ? 7
                             : tdpd                 ? 5 + static_cast<std::size_t>(tdpd_concentrations)
                                                    : 7;
    const std::string layout =
        style == "atomic"      ? "'id type x y z [ix iy iz]' (atom_style atomic)"
        : style == "molecular" ? "'id mol type x y z [ix iy iz]' (atom_style molecular)"
        : edpd                 ? "'id type edpd_temp edpd_cv x y z [ix iy iz]' (atom_style edpd)"
        : tdpd ? "'id type x y z cc1 .. cc" + std::to_string(tdpd_concentrations) + " [ix iy iz]' (atom_style tdpd, " +
                     std::to_string(tdpd_concentrations) + " solutes as in [tdpd] solutes)"
               : "'id mol type q x y z [ix iy iz]' (atom_style full)";
    for (const Line& line : atoms->lines) {
      const auto& t = line.tokens;
      if (t.size() != base && t.size() != base + 3) {
        p.fail(line, std::string("expected ") + layout + ", found " + std::to_string(t.size()) + " columns");
      }
      LammpsAtom a;
      a.id = static_cast<std::uint32_t>(p.integer(line, 0, "atom id", 1, kMaxCount));
      std::size_t c = 1;
      if (style == "molecular" || style == "full")
        a.mol = static_cast<std::int32_t>(p.integer(line, c++, "molecule id", 0, std::numeric_limits<std::int32_t>::max()));
      a.type = static_cast<int>(p.integer(line, c++, "atom type", 1, data.n_types));
      if (edpd) {
        a.temp = p.real(line, c++, "edpd_temp");
        a.cv = p.real(line, c++, "edpd_cv");
        if (!(a.temp > 0)) p.fail(line, "edpd_temp " + line.tokens[c - 2] + " of atom " + std::to_string(a.id) + " must be positive");
        if (!(a.cv > 0)) p.fail(line, "edpd_cv " + line.tokens[c - 1] + " of atom " + std::to_string(a.id) + " must be positive");
      }
      if (tdpd) {
        for (int k = 0; k < tdpd_concentrations; ++k) {
          const std::size_t col = 5 + static_cast<std::size_t>(k);
          a.conc[static_cast<std::size_t>(k)] = p.real(line, col, "concentration");
          if (a.conc[static_cast<std::size_t>(k)] < 0)
            p.fail(line, "concentration cc" + std::to_string(k + 1) + " = " + line.tokens[col] + " of atom " +
                             std::to_string(a.id) + " is negative");
        }
      }
      if (style == "full") {
        const double q = p.real(line, c++, "charge");
        if (q != 0.0)
          p.fail(line, "charge " + line.tokens[c - 1] + " of atom " + std::to_string(a.id) +
                           " is not zero: mesodpd has no electrostatics (atom_style full is read with zero charges only)");
      }
      a.x = p.real(line, c, "x");
      a.y = p.real(line, c + 1, "y");
      a.z = p.real(line, c + 2, "z");
      if (t.size() == base + 3) {
        constexpr std::int64_t lo = std::numeric_limits<std::int32_t>::min();
        constexpr std::int64_t hi = std::numeric_limits<std::int32_t>::max();
        a.ix = static_cast<std::int32_t>(p.integer(line, base, "image flag ix", lo, hi));
        a.iy = static_cast<std::int32_t>(p.integer(line, base + 1, "image flag iy", lo, hi));
        a.iz = static_cast<std::int32_t>(p.integer(line, base + 2, "image flag iz", lo, hi));
      }
      a.line = line.number;
      const auto [it, inserted] = line_of_id.emplace(a.id, line.number);
      if (!inserted) {
        p.fail(line, "duplicate atom id " + std::to_string(a.id) + " (first at line " +
                         std::to_string(it->second) + ")");
      }
      data.atoms.push_back(a);
    }

    if (velocities != nullptr) {
      if (velocities->lines.size() != data.atoms.size()) {
        p.fail(velocities->header, "Velocities section has " + std::to_string(velocities->lines.size()) +
                                       " lines, but there are " + std::to_string(data.atoms.size()) +
                                       " atoms");
      }
      std::unordered_map<std::uint32_t, std::size_t> index_of_id;
      for (std::size_t k = 0; k < data.atoms.size(); ++k) index_of_id.emplace(data.atoms[k].id, k);
      data.velocities.assign(data.atoms.size(), {0, 0, 0});
      std::vector<std::size_t> seen_at(data.atoms.size(), 0);
      for (const Line& line : velocities->lines) {
        if (line.tokens.size() != 4) p.fail(line, "expected 'id vx vy vz' in Velocities section");
        const auto id = static_cast<std::uint32_t>(p.integer(line, 0, "atom id", 1, kMaxCount));
        const auto it = index_of_id.find(id);
        if (it == index_of_id.end())
          p.fail(line,
                 "velocity given for atom id " + std::to_string(id) + ", which is not in the Atoms section");
        if (seen_at[it->second] != 0) {
          p.fail(line, "velocity of atom id " + std::to_string(id) + " given twice (first at line " +
                           std::to_string(seen_at[it->second]) + ")");
        }
        seen_at[it->second] = line.number;
        data.velocities[it->second] = {p.real(line, 1, "vx"), p.real(line, 2, "vy"), p.real(line, 3, "vz")};
      }
      data.has_velocities = true;
    }
  }
  if (velocities != nullptr && atoms == nullptr && !velocities->lines.empty()) {
    p.fail(velocities->header, "Velocities section without an Atoms section");
  }
  // Bonds, angles and dihedrals: "id type atom atom [atom [atom]]", every atom in the Atoms section.
  std::unordered_map<std::uint32_t, bool> known;
  for (const LammpsAtom& a : data.atoms) known.emplace(a.id, true);
  auto read_bonded = [&](const Section* sec, const char* what, std::int64_t declared, int n_types, std::size_t n_atoms_per,
                         std::vector<LammpsBonded>& out) {
    const std::string name = what;
    if (sec == nullptr) {
      if (declared > 0) p.fail("no " + name + " section, but the header declares " + std::to_string(declared) + " " +
                               (n_atoms_per == 2 ? "bonds" : n_atoms_per == 3 ? "angles" : "dihedrals"));
      return;
    }
    if (static_cast<std::int64_t>(sec->lines.size()) != declared)
      p.fail(sec->header, name + " section has " + std::to_string(sec->lines.size()) + " lines, but the header declares " +
                              std::to_string(declared));
    if (declared > 0 && n_types < 1)
      p.fail(sec->header, name + " section without a '" +
                              (n_atoms_per == 2 ? "bond" : n_atoms_per == 3 ? "angle" : "dihedral") +
                              " types' count in the header");
    std::unordered_map<std::uint32_t, std::size_t> line_of_id;
    for (const Line& line : sec->lines) {
      if (line.tokens.size() != 2 + n_atoms_per)
        p.fail(line, n_atoms_per == 2   ? "expected 'id type atom1 atom2' in Bonds section"
                     : n_atoms_per == 3 ? "expected 'id type atom1 atom2 atom3' in Angles section"
                                        : "expected 'id type atom1 atom2 atom3 atom4' in Dihedrals section");
      const auto id = static_cast<std::uint32_t>(p.integer(line, 0, (name + " id").c_str(), 1, kMaxCount));
      const auto [it, inserted] = line_of_id.emplace(id, line.number);
      if (!inserted)
        p.fail(line, "duplicate " + name + " id " + std::to_string(id) + " (first at line " + std::to_string(it->second) + ")");
      LammpsBonded b;
      b.type = static_cast<int>(p.integer(line, 1, (name + " type").c_str(), 1, std::max(1, n_types)));
      for (std::size_t k = 0; k < n_atoms_per; ++k) {
        b.atoms[k] = static_cast<std::uint32_t>(p.integer(line, 2 + k, "atom id", 1, kMaxCount));
        if (!known.count(b.atoms[k]))
          p.fail(line, name + " " + std::to_string(id) + " names atom " + std::to_string(b.atoms[k]) +
                           ", which is not in the Atoms section");
        for (std::size_t q = 0; q < k; ++q)
          if (b.atoms[q] == b.atoms[k])
            p.fail(line, name + " " + std::to_string(id) + " names atom " + std::to_string(b.atoms[k]) + " twice");
      }
      out.push_back(b);
    }
  };
  read_bonded(bonds, "Bonds", n_bonds, data.n_bond_types, 2, data.bonds);
  read_bonded(angles, "Angles", n_angles, data.n_angle_types, 3, data.angles);
  read_bonded(dihedrals, "Dihedrals", n_dihedrals, data.n_dihedral_types, 4, data.dihedrals);
  return data;
}

}  // namespace mesodpd
