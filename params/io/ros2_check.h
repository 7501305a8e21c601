// Checker for ROS 2 params files, applying the typing and structure rules of the ROS 2 YAML
// parameter parser (rcl_yaml_param_parser; ecosystem spec §3.1) with Debian's libyaml — the same
// event parser rcl uses — and the parameter types the car's node declares:
//   * the fully qualified node key with `ros__parameters` directly below (wildcards rejected);
//   * no anchors/aliases, no empty values, no empty arrays, no arrays of maps or arrays;
//   * scalar typing: quoted → string; else bool words, then integer (strtol over the whole token,
//     so 010 is octal), then double (strtod, .nan/.inf), else string;
//   * arrays homogeneous ("Sequence should be of same type");
//   * each value's literal type equal to the declared type (a mismatch makes the node throw at
//     start-up); non-finite values rejected;
//   * duplicate keys (the parser keeps the last), unknown keys (the node ignores them), keys the
//     node does not declare but the workspace uses, and declared keys left at the code default are
//     reported as warnings.
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"

namespace scw::params {

enum class ParamType { kBool, kInt, kDouble, kDoubleArray, kString };
const char* ParamTypeName(ParamType t);

struct DeclaredParam {
  std::string key;
  ParamType type;
  bool optional = false;
  bool workspace_only = false;
};

struct CheckFinding {
  bool error = true;  ///< false: warning
  std::string key;
  std::string message;
  int line = 0;
};

struct CheckReport {
  std::vector<CheckFinding> findings;
  bool ok() const;
  int errors() const;
  int warnings() const;
  /// One finding per line: `file:line: error|warning: key: message`.
  std::string Format(const std::string& file) const;
};

struct CheckOptions {
  std::string node_key;
  /// Warn about required keys that are absent (off for overrides-only files).
  bool expect_complete = true;
};

CheckReport CheckRosParamsText(const std::string& text, const std::vector<DeclaredParam>& declared,
                               const CheckOptions& options);

/// The declared parameter table of a schema struct.
template <class P>
std::vector<DeclaredParam> DeclaredParams() {
  std::vector<DeclaredParam> out;
  const P p{};
  ForEachField(p, [&](const std::string& path, const auto& value, const Meta& meta) {
    using T = std::decay_t<decltype(value)>;
    ParamType t = ParamType::kString;
    if constexpr (std::is_same_v<T, bool>) t = ParamType::kBool;
    if constexpr (std::is_same_v<T, int>) t = ParamType::kInt;
    if constexpr (std::is_same_v<T, double>) t = ParamType::kDouble;
    if constexpr (std::is_same_v<T, std::vector<double>>) t = ParamType::kDoubleArray;
    out.push_back({path, t, meta.optional, meta.workspace_only});
  });
  return out;
}

}  // namespace scw::params
