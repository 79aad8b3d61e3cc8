// ConfigError: a configuration problem, always naming the offending key, file or value. Its own small
// header so that every module can throw it without including the whole schema (spec.hpp).
#pragma once
#include <stdexcept>
#include <string>

namespace mesodpd {

class ConfigError : public std::runtime_error {
 public:
  explicit ConfigError(const std::string& what, std::string key = {})
      : std::runtime_error(what), key_(std::move(key)) {}
  // The full key the problem is about, as the TOML schema spells it ("pair.override[1].rd"), where the
  // error is about one key (the TOML reader and validate() set it); empty otherwise.
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

}  // namespace mesodpd
