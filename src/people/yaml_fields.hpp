#pragma once
// A config struct as YAML text, one member a key: how each member prints and parses, with the
// comment that carries its unit. Private to people/ (yaml-cpp stays out of the public headers).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::people::yaml_fields {

template <class Config>
struct Field {
  std::function<std::string(const Config&)> print;
  std::function<void(Config&, const YAML::Node&)> parse;
  const char* comment;
};

template <class Config>
using Fields = std::vector<std::pair<std::string, Field<Config>>>;

/// The field of `member`; a floating-point value must be finite.
template <class Config, class T>
Field<Config> field(T Config::*member, const char* comment) {
  Field<Config> f;
  f.comment = comment;
  f.print = [member](const Config& c) {
    if constexpr (std::is_same_v<T, std::string>) {
      return "\"" + c.*member + "\"";
    } else if constexpr (std::is_same_v<T, bool>) {
      return std::string(c.*member ? "true" : "false");
    } else if constexpr (std::is_integral_v<T>) {
      return std::to_string(c.*member);
    } else {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.6g", double(c.*member));
      return std::string(buf);
    }
  };
  f.parse = [member](Config& c, const YAML::Node& n) {
    const T v = n.as<T>();
    if constexpr (std::is_floating_point_v<T>)
      if (!std::isfinite(v)) throw YAML::Exception(YAML::Mark::null_mark(), "not finite");
    c.*member = v;
  };
  return f;
}

/// "  key: value  # comment" lines under `section:`.
template <class Config>
std::string print(const Fields<Config>& fields, const Config& c, const std::string& section) {
  std::string s = section + ":\n";
  for (const auto& [key, f] : fields)
    s += "  " + key + ": " + f.print(c) + "  # " + f.comment + "\n";
  return s;
}

/// Parses the keys of `map` onto `c`; throws Error naming `source`, `what` and the key for an
/// unknown key or a bad value. Keys in `skip` are left to another reader.
template <class Config>
void parse(const Fields<Config>& fields, const YAML::Node& map, Config& c,
           const std::string& source, const char* what, const std::vector<std::string>& skip = {}) {
  if (!map.IsMap()) throw Error(source + ": expected a map of " + what + " settings");
  for (const auto& kv : map) {
    const auto key = kv.first.as<std::string>();
    if (std::find(skip.begin(), skip.end(), key) != skip.end()) continue;
    const auto it =
        std::find_if(fields.begin(), fields.end(), [&](const auto& f) { return f.first == key; });
    if (it == fields.end()) throw Error(source + ": unknown " + what + " setting '" + key + "'");
    try {
      it->second.parse(c, kv.second);
    } catch (const YAML::Exception&) {
      throw Error(source + ": setting '" + key + "' has a bad value '" +
                  (kv.second.IsScalar() ? kv.second.as<std::string>() : std::string("?")) + "'");
    }
  }
}

/// The document's root; throws Error naming `source` when the text is not YAML.
inline YAML::Node load(const std::string& text, const std::string& source) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw Error(source + ": not valid YAML: " + e.what());
  }
}

}  // namespace fieldlidar::people::yaml_fields
