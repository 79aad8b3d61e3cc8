#include "engine/transported_scalars.hpp"

#include <string_view>

#include <fmt/format.h>

#include "engine/pair_laws.hpp"
#include "mesodpd/key_table.hpp"
#include "physics/pair_force.hpp"

namespace mesodpd {

void check_scalar_field(const std::string& field, const SimulationSpec& spec, const std::string& key) {
  const std::string_view style = pair_law(spec.pair_style).style;
  const bool temp = field == "temp";
  const bool conc = field.size() == 5 && field.starts_with("conc") && field[4] >= '1' && field[4] <= '0' + kMaxScalars;
  if (!temp && !conc) keys::fail(key, "\"" + field + "\"", "expected \"temp\" (eDPD) or \"conc1\" .. \"conc4\" (tDPD)");
  const std::string_view need = temp ? "edpd" : "tdpd";
  if (style != need)
    keys::fail(key, "\"" + field + "\"", fmt::format("needs pair.style = \"{}\" (this run's is \"{}\")", need, style));
}

void require_held(const ParticleData& p, const std::string& field, const std::string& key, const std::string& value) {
  if (!p.enabled(field))
    throw SpecError(key, value, fmt::format("the run does not carry {} ([tdpd] solutes is smaller)", field));
}

}  // namespace mesodpd
