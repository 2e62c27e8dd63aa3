#pragma once
// Typed configuration. A config struct names its fields once, in a Visit member:
//
//   struct PushConfig {
//     bool enabled = true;
//     double interval_s = 15.0;
//     template <class V> void Visit(V& v) {
//       v("enabled", enabled);
//       v("interval_s", interval_s, Bounds<double>{0.02, 3600.0});
//     }
//   };
//
// and that one list serves reading (ConfigReader: strict, with messages naming the file and key),
// writing (ToYaml: the resolved config echoed to logs, run folders and skill-library metadata) and
// defaults (the in-class initialisers). Missing keys keep their defaults; unknown keys are errors.

#include <yaml-cpp/yaml.h>

#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/check.h"

namespace flsd {

// A closed interval [lo, hi], written in YAML as [lo, hi].
struct Interval {
  double lo = 0.0;
  double hi = 0.0;
  bool operator==(const Interval& o) const { return lo == o.lo && hi == o.hi; }
};

// Inclusive bounds on a numeric field (or on both ends of an Interval).
template <class T>
struct Bounds {
  T lo;
  T hi;
};

namespace config_detail {
struct Probe {
  template <class... A>
  void operator()(A&&...) {}
};
template <class T, class = void>
struct IsSection : std::false_type {};
template <class T>
struct IsSection<T, std::void_t<decltype(std::declval<T&>().Visit(std::declval<Probe&>()))>>
    : std::true_type {};
template <class T>
struct IsVector : std::false_type {};
template <class T>
struct IsVector<std::vector<T>> : std::true_type {};
template <class T>
std::string Show(const T& v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace config_detail

class ConfigReader {
 public:
  // `where` prefixes every message, e.g. "configs/smoke.yaml: env".
  ConfigReader(YAML::Node node, std::string where);

  template <class T>
  void operator()(const char* key, T& value) {
    Read(key, value);
  }
  template <class T, class B>
  void operator()(const char* key, T& value, Bounds<B> bounds) {
    Read(key, value);
    CheckBounds(key, value, bounds);
  }

  // Throws InputError if the section has keys that no field claimed.
  void Finish() const;

 private:
  template <class T>
  void Read(const char* key, T& value);
  template <class T, class B>
  void CheckBounds(const char* key, const T& value, Bounds<B> bounds) const;
  [[noreturn]] void Fail(const char* key, const std::string& expected, const YAML::Node& got) const;
  std::string Where(const char* key) const;

  YAML::Node node_;
  std::string where_;
  std::set<std::string> claimed_;
};

class ConfigWriter {
 public:
  template <class T>
  void operator()(const char* key, T& value) {
    if constexpr (config_detail::IsSection<T>::value) {
      ConfigWriter sub;
      value.Visit(sub);
      node_[key] = sub.node_;
    } else if constexpr (std::is_same_v<T, Interval>) {
      YAML::Node pair(YAML::NodeType::Sequence);
      pair.push_back(value.lo);
      pair.push_back(value.hi);
      pair.SetStyle(YAML::EmitterStyle::Flow);
      node_[key] = pair;
    } else if constexpr (config_detail::IsVector<T>::value) {
      YAML::Node list(YAML::NodeType::Sequence);
      for (const auto& item : value) list.push_back(item);
      list.SetStyle(YAML::EmitterStyle::Flow);
      node_[key] = list;
    } else {
      node_[key] = value;
    }
  }
  template <class T, class B>
  void operator()(const char* key, T& value, Bounds<B>) {
    (*this)(key, value);
  }
  const YAML::Node& node() const { return node_; }

 private:
  YAML::Node node_{YAML::NodeType::Map};
};

// Reads `config` from `node`, strictly; `where` names the file and section for messages.
template <class T>
void ReadConfig(const YAML::Node& node, const std::string& where, T& config) {
  ConfigReader reader(node, where);
  config.Visit(reader);
  reader.Finish();
}

// Parses a YAML file; throws InputError naming the file (and line) when it is absent or malformed.
YAML::Node LoadYamlFile(const std::string& path);

// A config file as its sections will read it:
// - `base: other.yaml` (a path relative to the file) loads that file first, and this file's keys
//   replace the base's: mappings merge key by key, anything else (values, lists) is replaced whole.
//   Bases may have bases; a cycle is an error.
// - each of `overrides`, "key.path=value" (the form of a `--set` option), then sets one key; the
//   value is read as YAML ("0.3", "true", "[1, 2]"). Keys are not checked here: the strict
//   ConfigReader names an unknown one.
YAML::Node LoadConfigFile(const std::string& path, const std::vector<std::string>& overrides = {});

// Loads section `section` of the YAML file at `path` into a T (defaults for missing keys).
template <class T>
T LoadConfigSection(const std::string& path, const std::string& section) {
  const YAML::Node root = LoadConfigFile(path);
  if (!root.IsMap() || !root[section]) {
    throw InputError(path + ": missing section '" + section + "'");
  }
  T config;
  ReadConfig(root[section], path + ": " + section, config);
  return config;
}

template <class T>
YAML::Node ToYaml(const T& config) {
  T copy = config;
  ConfigWriter writer;
  copy.Visit(writer);
  return writer.node();
}

template <class T>
std::string ToYamlString(const T& config) {
  YAML::Emitter out;
  out << ToYaml(config);
  return out.c_str();
}

// ---- implementation ----

template <class T>
void ConfigReader::Read(const char* key, T& value) {
  claimed_.insert(key);
  if (!node_.IsMap()) return;
  const YAML::Node item = node_[key];
  if (!item.IsDefined() || item.IsNull()) return;
  if constexpr (config_detail::IsSection<T>::value) {
    if (!item.IsMap()) Fail(key, "a mapping of keys", item);
    ReadConfig(item, Where(key), value);
  } else if constexpr (std::is_same_v<T, Interval>) {
    if (!item.IsSequence() || item.size() != 2) Fail(key, "a range [lo, hi]", item);
    try {
      value = Interval{item[0].as<double>(), item[1].as<double>()};
    } catch (const YAML::Exception&) {
      Fail(key, "a range [lo, hi] of numbers", item);
    }
    if (!(value.lo <= value.hi)) Fail(key, "a range [lo, hi] with lo <= hi", item);
  } else if constexpr (config_detail::IsVector<T>::value) {
    if (!item.IsSequence()) Fail(key, "a list [a, b, ...]", item);
    try {
      value = item.as<T>();
    } catch (const YAML::Exception&) {
      Fail(key, "a list of numbers", item);
    }
  } else {
    if (!item.IsScalar()) Fail(key, "a single value", item);
    try {
      value = item.as<T>();
    } catch (const YAML::Exception&) {
      if constexpr (std::is_same_v<T, bool>) Fail(key, "true or false", item);
      if constexpr (std::is_integral_v<T>) Fail(key, "an integer", item);
      if constexpr (std::is_floating_point_v<T>) Fail(key, "a number", item);
      Fail(key, "a string", item);
    }
  }
}

template <class T, class B>
void ConfigReader::CheckBounds(const char* key, const T& value, Bounds<B> bounds) const {
  auto inside = [&](double x) { return x >= bounds.lo && x <= bounds.hi; };
  const std::string range =
      "[" + config_detail::Show(bounds.lo) + ", " + config_detail::Show(bounds.hi) + "]";
  if constexpr (std::is_same_v<T, Interval>) {
    if (!inside(value.lo) || !inside(value.hi)) {
      throw InputError(Where(key) + ": expected both ends within " + range + ", got [" +
                       config_detail::Show(value.lo) + ", " + config_detail::Show(value.hi) + "]");
    }
  } else if constexpr (config_detail::IsVector<T>::value) {
    for (const auto& x : value) {
      if (!inside(static_cast<double>(x))) {
        throw InputError(Where(key) + ": expected every entry within " + range + ", got " +
                         config_detail::Show(x));
      }
    }
  } else if (!inside(static_cast<double>(value))) {
    throw InputError(Where(key) + ": expected a value within " + range + ", got " +
                     config_detail::Show(value));
  }
}

}  // namespace flsd
