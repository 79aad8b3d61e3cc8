// Numbers for the JSON summaries: 8 significant digits, written the way printf's %.8g writes them.
#pragma once
#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <nlohmann/json.hpp>

namespace mesodpd {

// `v` rounded to 8 significant digits; an integral result becomes a JSON integer, so the text reads
// "3", "0.02", "2.5722156", "1e-05" as %.8g would print it. nlohmann writes a decimal that reads back
// as the double (Grisu2), which for a number parsed from 8 digits is those digits except about once in
// 1,200, where it spells the same double with 16 or 17 (930.4414399999999 for 930.44144). NaN and
// infinity become null: JSON has no such numbers.
inline nlohmann::ordered_json json_number(double v) {
  if (!std::isfinite(v)) return nullptr;
  const double r = std::strtod(fmt::format("{:.8g}", v).c_str(), nullptr);
  if (r == std::trunc(r) && std::fabs(r) < 1e15) return static_cast<std::int64_t>(r);
  return r;
}

}  // namespace mesodpd
