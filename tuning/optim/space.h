// The tuner's search space over the stability parameters, mapped to the unit cube [0,1]^n that
// NLopt works in.
//
// Each dimension u_i ∈ [0,1] maps to a value x_i ∈ [lo, hi] linearly or on a log10 scale, and x_i
// is applied to a parameter by one of four transforms, in the order the entries are listed:
//   direct       key := x                      (key may name one array element: key[i])
//   offset       key := value(of) + x          (orderings: e.g. reduce_hold = hold_reduce + x, x<0)
//   ratio        key := min(value(of)) · x     (hysteresis: deactivation = x · activation, x<1)
//   scale_array  key[j] := base[j] · x for all j (velocity-scheduled arrays keep shape and length)
// `value(of)` is the already decoded value (entries earlier in the list) or the base value.
// Re-parameterising orderings and hysteresis pairs this way keeps almost every point of the cube
// valid; a decoded set that still violates a schema rule is reported as infeasible (the cost then
// gives a finite penalty), never thrown through the optimiser.
//
// Space file (plain YAML):
//   name: default
//   parameters:
//     - {key: ESC.kp_psi_dot, lo: 2.0, hi: 30.0, scale: log}
//     - {key: ESC.beta_threshold_deactivate, transform: ratio, of: ESC.beta_threshold_activate,
//        lo: 0.4, hi: 1.2}
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"
#include "params/schema/stability_params.h"

namespace scw::tuning {

enum class Transform { kDirect, kOffset, kRatio, kScaleArray };

struct SpaceEntry {
  std::string key;  ///< dotted key of a double or double[] parameter
  int index = -1;   ///< array element (direct only), -1 = the whole parameter
  double lo = 0.0;  ///< bounds of x (the transform's argument)
  double hi = 1.0;
  params::Scale scale = params::Scale::kLinear;
  Transform transform = Transform::kDirect;
  std::string of;  ///< reference key (offset, ratio)
  int of_index = -1;
  std::string Label() const;  ///< e.g. "ESC.kp_psi_dot", "ESC.threshold_velocities[0]"
};

class ParameterSpace {
 public:
  /// Throws ConfigError (file, key path, rule) on a bad space description.
  ParameterSpace(std::string name, std::vector<SpaceEntry> entries);
  static ParameterSpace FromYamlText(const std::string& text, const std::string& file);
  static ParameterSpace FromFile(const std::string& path);
  /// The built-in default space (ESC thresholds and both PIDs, countersteer, ABS and TC slip
  /// thresholds); identical to params/spaces/default.yaml.
  static ParameterSpace Default();

  const std::string& name() const { return name_; }
  int size() const { return static_cast<int>(entries_.size()); }
  const std::vector<SpaceEntry>& entries() const { return entries_; }

  /// Maps u ∈ [0,1]^n (clamped) to a parameter set, starting from `base`. `problems` receives the
  /// schema violations of the result (empty: feasible).
  params::StabilityParams Decode(const std::vector<double>& u, const params::StabilityParams& base,
                                 Problems* problems) const;
  /// x_i of each dimension for u (the transform arguments, for logs).
  std::vector<double> Arguments(const std::vector<double>& u) const;
  /// The point of the cube that reproduces `p` as closely as the bounds allow (start point).
  std::vector<double> Encode(const params::StabilityParams& p) const;
  /// YAML text of this space (round-trips through FromYamlText).
  std::string ToYaml() const;

 private:
  std::string name_;
  std::vector<SpaceEntry> entries_;
};

}  // namespace scw::tuning
