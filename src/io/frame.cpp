// Field parsing, frame validation and id ordering shared by the trajectory writers.
#include "io/frame.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>
#include <string_view>
#include <utility>

#include "mesodpd/config_error.hpp"

namespace mesodpd {

namespace {

// The list's fields that make up the six standard selections, bound to the frame's named pointers.
bool bind_standard(FrameView& f, std::string_view name, const double* d) {
  static constexpr std::pair<std::string_view, const double* FrameView::*> table[] = {
      {"x", &FrameView::x},   {"y", &FrameView::y},   {"z", &FrameView::z},   {"vx", &FrameView::vx},
      {"vy", &FrameView::vy}, {"vz", &FrameView::vz}, {"fx", &FrameView::fx}, {"fy", &FrameView::fy},
      {"fz", &FrameView::fz}};
  for (const auto& [n, member] : table)
    if (n == name) {
      f.*member = d;
      return true;
    }
  return false;
}
bool bind_standard(FrameView& f, std::string_view name, const std::int32_t* d) {
  static constexpr std::pair<std::string_view, const std::int32_t* FrameView::*> table[] = {
      {"species", &FrameView::species}, {"ix", &FrameView::ix}, {"iy", &FrameView::iy}, {"iz", &FrameView::iz}};
  for (const auto& [n, member] : table)
    if (n == name) {
      f.*member = d;
      return true;
    }
  return false;
}
bool bind_standard(FrameView& f, std::string_view name, const std::uint32_t* d) {
  if (name != "id") return false;
  f.id = d;
  return true;
}
template <class T>
bool bind_standard(FrameView&, std::string_view, const T*) {
  return false;
}

}  // namespace

void set_frame_arrays(FrameView& f, const ParticleData& p) {
  f.n = p.n_local;
  f.extra.clear();
  p.for_each_field([&](const FieldInfo& info, const auto& v) {
    if (!(info.flags & field::kFrame)) return;
    if (!bind_standard(f, info.name, v.data())) f.extra.push_back({info.name, info.kind, info.elem_bytes, v.data()});
  });
}

const std::vector<std::string>& trajectory_field_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out = {"id", "species", "position", "velocity", "force", "image"};
    FrameView probe;
    ParticleData every;  // the optional fields too: a run holds them where its model enables them
    for (const FieldInfo& info : ParticleData::fields())
      if (info.flags & field::kOptional) every.enable(info.name);
    set_frame_arrays(probe, every);
    for (const auto& e : probe.extra) out.push_back(e.name);
    return out;
  }();
  return names;
}

FieldSet parse_trajectory_fields(const std::vector<std::string>& names, const std::filesystem::path& file) {
  const std::string where = "trajectory '" + file.string() + "'";
  if (names.empty()) throw ConfigError(where + ": the list of fields is empty");
  FieldSet set;
  for (const std::string& name : names) {
    bool* flag = nullptr;
    if (name == "id")
      flag = &set.id;
    else if (name == "species")
      flag = &set.species;
    else if (name == "position")
      flag = &set.position;
    else if (name == "velocity")
      flag = &set.velocity;
    else if (name == "force")
      flag = &set.force;
    else if (name == "image")
      flag = &set.image;
    const auto& all = trajectory_field_names();
    if (flag == nullptr && std::find(all.begin() + 6, all.end(), name) != all.end()) {
      if (std::find(set.extra.begin(), set.extra.end(), name) != set.extra.end())
        throw ConfigError(where + ": field '" + name + "' is listed twice");
      set.extra.push_back(name);
      continue;
    }
    if (flag == nullptr) {
      std::string expected;
      for (std::size_t k = 0; k < all.size(); ++k) expected += (k == 0 ? "" : (k + 1 == all.size() ? " or " : ", ")) + all[k];
      throw ConfigError(where + ": unknown field '" + name + "' (expected " + expected + ")");
    }
    if (*flag) throw ConfigError(where + ": field '" + name + "' is listed twice");
    *flag = true;
  }
  // Extras in the order of the particle field list.
  const auto& all = trajectory_field_names();
  std::sort(set.extra.begin(), set.extra.end(), [&](const std::string& a, const std::string& b) {
    return std::find(all.begin(), all.end(), a) < std::find(all.begin(), all.end(), b);
  });
  return set;
}

const FrameView::Extra& extra_array(const FrameView& f, const std::string& name) {
  for (const auto& e : f.extra)
    if (e.name == name) return e;
  throw ConfigError("trajectory frame at step " + std::to_string(f.step) + ": no '" + name + "' array");
}

void check_frame_arrays(const FrameView& f, const FieldSet& fields, const std::filesystem::path& file) {
  const std::string where = "trajectory '" + file.string() + "', step " + std::to_string(f.step);
  for (int d = 0; d < 3; ++d) {
    if (!(f.box_len[d] > 0)) throw ConfigError(where + ": box length must be positive");
  }
  if (f.n == 0) return;
  auto need = [&](bool wanted, bool present, const char* what) {
    if (wanted && !present) throw ConfigError(where + ": frame has no " + std::string(what) + " array");
  };
  need(true, f.id != nullptr, "id");
  need(fields.species, f.species != nullptr, "species");
  need(fields.position, f.x && f.y && f.z, "position");
  need(fields.velocity, f.vx && f.vy && f.vz, "velocity");
  need(fields.force, f.fx && f.fy && f.fz, "force");
  need(fields.image, f.ix && f.iy && f.iz, "image");
  for (const std::string& name : fields.extra) {
    bool present = false;
    for (const auto& e : f.extra) present = present || (e.name == name && e.data != nullptr);
    need(true, present, name.c_str());
  }
  if (fields.species) {
    for (std::size_t i = 0; i < f.n; ++i) {
      const bool named =
          f.species_names == nullptr || static_cast<std::size_t>(f.species[i]) < f.species_names->size();
      if (f.species[i] < 0 || !named) {
        throw ConfigError(where + ": particle id " + std::to_string(f.id[i]) + " has species index " +
                          std::to_string(f.species[i]) + ", which is not a valid species");
      }
    }
  }
}

std::vector<std::size_t> order_by_id(const FrameView& f, const std::filesystem::path& file) {
  std::vector<std::size_t> order(f.n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  if (f.n == 0) return order;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return f.id[a] < f.id[b]; });
  for (std::size_t k = 1; k < order.size(); ++k) {
    if (f.id[order[k]] == f.id[order[k - 1]]) {
      throw ConfigError("trajectory '" + file.string() + "', step " + std::to_string(f.step) +
                        ": particle id " + std::to_string(f.id[order[k]]) + " appears twice in the frame");
    }
  }
  return order;
}

}  // namespace mesodpd
