// The texts and checks of declared keys (include/mesodpd/key_table.hpp): refusals as validate() words
// them, and the rows of docs/config.md.
#include "mesodpd/key_table.hpp"

#include <fmt/format.h>

namespace mesodpd {

SpecError::SpecError(std::string key, std::string value, std::string why)
    : ConfigError(value.empty() ? fmt::format("{}: {}", key, why) : fmt::format("{} = {}: {}", key, value, why), key),
      value_(std::move(value)),
      why_(std::move(why)) {}

namespace keys {

std::string Range::text() const {
  if (lo == -kInf && hi == kInf) return "must be a finite number";
  if (hi == kInf) return fmt::format("must be {} {}", lo_closed ? ">=" : ">", lo);
  return fmt::format("must be in {}{}, {}{}", lo_closed ? '[' : '(', lo, hi, hi_closed ? ']' : ')');
}

std::string Range::doc() const {
  if (lo == -kInf && hi == kInf) return "finite";
  if (hi == kInf) return fmt::format("{} {}", lo_closed ? ">=" : ">", lo);
  return fmt::format("{}{}, {}{}", lo_closed ? '[' : '(', lo, hi, hi_closed ? ']' : ')');
}

std::string IntRange::doc() const {
  constexpr long long kMin = std::numeric_limits<long long>::min(), kMax = std::numeric_limits<long long>::max();
  if (lo == kMin && hi == kMax) return "";
  if (hi == kMax) return fmt::format(">= {}", lo);
  if (lo == kMin) return fmt::format("<= {}", hi);
  return fmt::format("{} to {}", lo, hi);
}

void fail(const std::string& key, std::string value, std::string why) {
  throw SpecError(key, std::move(value), std::move(why));
}

std::string show(double v) { return fmt::format("{}", v); }

void check(const std::string& key, double v, Range r) {
  if (!r.contains(v)) fail(key, show(v), r.text());
}

void check_int(const std::string& key, long long v, IntRange r) {
  if (v < r.lo) fail(key, fmt::format("{}", v), fmt::format("must be an integer >= {}", r.lo));
  if (v > r.hi) fail(key, fmt::format("{}", v), fmt::format("must be an integer <= {}", r.hi));
}

std::string fill_in(std::string text, std::string_view key, std::string_view value) {
  for (const auto& [token, with] : {std::pair<std::string_view, std::string_view>{"{key}", key}, {"{value}", value}})
    for (std::size_t at = text.find(token); at != std::string::npos; at = text.find(token, at + with.size()))
      text.replace(at, token.size(), with);
  return text;
}

std::string doc_number(double v) {
  if (std::isfinite(v) && v == std::trunc(v) && std::abs(v) < 1e15) return fmt::format("{:.1f}", v);
  return fmt::format("{}", v);
}

std::string quoted_words(const std::vector<std::string_view>& words, std::string_view quote, std::string_view sep) {
  std::string out;
  for (const std::string_view w : words) out += fmt::format("{}`{}{}{}`", out.empty() ? "" : sep, quote, w, quote);
  return out;
}

std::string markdown(const std::vector<KeyDoc>& rows) {
  std::string out = "| key | type | default | allowed | meaning |\n|---|---|---|---|---|\n";
  for (const KeyDoc& r : rows)
    out += fmt::format("| `{}` | {} | {} | {}| {} |\n", r.name, r.type, r.default_text,
                       r.allowed.empty() ? "" : r.allowed + " ", r.meaning);
  return out;
}

}  // namespace keys
}  // namespace mesodpd
