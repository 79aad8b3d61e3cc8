// Field parsing, frame validation and id ordering shared by the trajectory writers.
#include "io/frame.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>

#include "mesodpd/spec.hpp"

namespace mesodpd {

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
    if (flag == nullptr) {
      throw ConfigError(where + ": unknown field '" + name +
                        "' (expected id, species, position, velocity, force or image)");
    }
    if (*flag) throw ConfigError(where + ": field '" + name + "' is listed twice");
    *flag = true;
  }
  return set;
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
