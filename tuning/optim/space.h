// The tuner's search space over the stability parameters, mapped to the unit cube [0,1]^n that
// NLopt works in.
//
// Each dimension u_i ∈ [0,1] maps to a value x_i ∈ [lo, hi] linearly or on a log10 scale, and x_i
// is applied to a parameter by one of four transforms, in the order the entries are listed:
//   direct       key := x                      (key may name one array element: key[i])
//   offset       key := value(of) + x          (orderings: e.g. reduce_hold = hold_reduce + x, x<0)
//   ratio        key := ref(of) · x            (hysteresis: deactivation = x · activation, x<1)
//   scale_array  key[j] := base[j] · x for all j (velocity-scheduled arrays keep shape and length)
// `value(of)` is the already decoded value (entries earlier in the list) or the base value;
// ref(of) is value(of) for a scalar or one element (key[i]), and for a whole array its smallest
// value — for the velocity-scheduled ESC thresholds the smallest value the car's node
// interpolates (outer segments extended) at the speeds where `scw params check` checks the
// hysteresis (params::ScheduledMinimum), so that x < 1 keeps the deactivation below the
// activation threshold at every speed and a tuned set adds no inverted-hysteresis finding;
// the smallest element where that schedule is not positive (the base then has the finding too).
// Re-parameterising orderings and hysteresis pairs this way keeps almost every point of the cube
// valid; a decoded set that still violates a schema rule is reported as infeasible (the cost then
// gives a finite penalty), never thrown through the optimiser.
//
// The tuner never changes what it did not tune (these files go onto the car):
//   * Keys no entry names are copied from the base, bit for bit.
//   * The base is exactly representable: for a space fitted to it (WithBase), Encode(base) decodes
//     back to the base bit for bit. A dimension whose u equals the base's own coordinate, and whose
//     reference (`of`) still has its base value, takes the base value itself rather than the
//     transform's floating-point round trip (0.6 → 0.6000000000000002, or x·ref ≠ base for a
//     ratio).
//   * Where a base value lies outside an entry's range (the shipped ESC.beta_threshold_deactivate
//   is
//     2.01 × min(ESC.beta_threshold_activate), outside the ratio range [0.3, 1]), WithBase grows
//     the range to include it (default: scw tune) or refuses naming the key (kRefuse). Without
//     that, the value would be clamped into the range and silently changed by every tune.
//   * Every decoded value is quantised to its field's schema resolution (Meta::resolution): a value
//     within one step of its base value is the base value, anything else a multiple of the
//     resolution (shortest decimal text), chosen so that the entry's range — and with it the
//     ordering or hysteresis its transform guarantees — and the schema bounds still hold. What the
//     tuner evaluates is therefore exactly what it exports, and the overrides file lists only real
//     changes.
//
// Space file (plain YAML, described once by SpaceFile below: the strict loader, the writer and the
// docs table derive from it):
//   name: default
//   parameters:
//     - {key: ESC.kp_psi_dot, lo: 2.0, hi: 30.0, scale: log}
//     - {key: ESC.beta_threshold_deactivate, transform: ratio, of: ESC.beta_threshold_activate,
//        lo: 0.4, hi: 1.2}
// The rules that need the stability schema (the key exists, ranges within its bounds, index in
// range, each key tuned once) are checked by the ParameterSpace constructor, for files and code
// alike.
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"
#include "params/schema/stability_params.h"

namespace scw::tuning {

enum class Transform { kDirect, kOffset, kRatio, kScaleArray };

/// What WithBase does with a base value outside an entry's range.
enum class BaseOutsideSpace {
  kGrow,    ///< widen the range to include it (rounded outward to 3 significant digits)
  kRefuse,  ///< throw ConfigError naming the key
};

/// One entry whose range does not contain the base's transform argument.
struct BaseMismatch {
  int index = -1;                     ///< entry index
  std::string label;                  ///< SpaceEntry::Label()
  double x_base = 0;                  ///< the base's argument (NaN: cannot be represented at all)
  double lo = 0, hi = 0;              ///< the entry's range
  double grown_lo = 0, grown_hi = 0;  ///< the range WithBase(kGrow) uses
  bool representable = true;          ///< false: no range can hold it (see message)
  std::string message;                ///< one sentence naming the key, the value and the range
};

struct SpaceEntry {
  std::string key;  ///< dotted key of a double or double[] parameter
  int index = -1;   ///< array element (direct only), -1 = the whole parameter
  double lo = 0.0;  ///< bounds of x (the transform's argument)
  double hi = 1.0;
  params::Scale scale = params::Scale::kLinear;
  Transform transform = Transform::kDirect;
  std::string of;  ///< reference key (offset, ratio)
  int of_index = -1;
  /// Pinned (ParameterSpace::WithPinned): Decode ignores u and keeps the key at its base value —
  /// for a relative entry whose reference moved, the base value itself while the argument that
  /// gives it lies in [lo, hi], else the nearest value that keeps the ordering or hysteresis.
  bool pinned = false;
  std::string Label() const;  ///< e.g. "ESC.kp_psi_dot", "ESC.threshold_velocities[0]"
};

/// One entry of a space file: the text form of a SpaceEntry.
struct SpaceFileEntry {
  std::string key;
  std::string transform = "direct";
  std::string of;
  double lo = 0.0;
  double hi = 1.0;
  std::string scale = "linear";

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.key, {.key = "key",
                    .doc = "Dotted key of a double or double[] stability parameter; key[i] names "
                           "one element of an array (direct, offset, ratio)."});
    v.Field(
        s.transform,
        {.key = "transform",
         .doc = "How the argument x sets the key: direct (key = x), offset "
                "(key = of + x), ratio (key = ref(of) · x: for an array its smallest value, for a "
                "velocity-scheduled ESC threshold the smallest value the car interpolates between "
                "ESC.min_activation_velocity and 90 m/s), scale_array (every "
                "element of the base array × x).",
         .optional = true,
         .choices = "direct|offset|ratio|scale_array",
         .omit_default = true});
    v.Field(s.of, {.key = "of",
                   .doc = "Reference key of offset and ratio (key[i] for one element); its value "
                          "as decoded by an earlier entry, else the base value.",
                   .optional = true,
                   .omit_default = true});
    v.Field(s.lo, {.key = "lo", .doc = "Lower bound of the argument x."});
    v.Field(s.hi, {.key = "hi", .doc = "Upper bound of the argument x."});
    v.Field(s.scale, {.key = "scale",
                      .doc = "How u ∈ [0, 1] maps to x: linear, or log (log10, needs lo > 0).",
                      .optional = true,
                      .choices = "linear|log"});
  }
};

/// A space file (params/spaces/*.yaml).
struct SpaceFile {
  std::string name = "space";
  std::vector<SpaceFileEntry> parameters;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.name, {.key = "name", .doc = "Name of the space (logs, reports).", .optional = true});
    v.List(s.parameters, {.key = "parameters",
                          .doc = "The dimensions of the search space, in decoding order.",
                          .min_size = 1});
  }
};

class ParameterSpace {
 public:
  /// Throws ConfigError (file, key path, rule) on a bad space description.
  ParameterSpace(std::string name, std::vector<SpaceEntry> entries);
  static ParameterSpace FromYamlText(const std::string& text, const std::string& file);
  static ParameterSpace FromFile(const std::string& path);
  /// The built-in default space: params/spaces/default.yaml, embedded at build time. ESC
  /// activation thresholds keep their velocity shape and scale as a whole, the deactivation
  /// thresholds follow as fractions of the smallest activation value (valid hysteresis by
  /// construction); both PIDs on log scales (gains span decades); countersteer; the ABS slip
  /// thresholds per axle and the TC rear ones: hold_reduce directly, the rest as ratios and
  /// ordered gaps.
  static ParameterSpace Default();

  const std::string& name() const { return name_; }
  int size() const { return static_cast<int>(entries_.size()); }
  const std::vector<SpaceEntry>& entries() const { return entries_; }

  /// Maps u ∈ [0,1]^n (clamped) to a parameter set, starting from `base`: keys outside the space
  /// keep the base values, tuned values are quantised to their schema resolution (see above).
  /// `problems` receives the schema violations of the result (empty: feasible).
  params::StabilityParams Decode(const std::vector<double>& u, const params::StabilityParams& base,
                                 Problems* problems) const;
  /// x_i of each dimension for u (the transform arguments, for logs).
  std::vector<double> Arguments(const std::vector<double>& u) const;
  /// The point of the cube that reproduces `p` as closely as the bounds allow (start point). When
  /// every argument of `p` lies within its range (BaseMismatches(p) is empty),
  /// Decode(Encode(p), p) == p bit for bit.
  std::vector<double> Encode(const params::StabilityParams& p) const;

  /// The entries whose range does not contain the argument of `base` (empty: the base is exactly
  /// representable). Used by `scw space show` to warn.
  std::vector<BaseMismatch> BaseMismatches(const params::StabilityParams& base) const;
  /// This space with each range grown to contain the base's argument (kGrow; `notes` receives one
  /// line per grown entry), or this space unchanged when nothing lies outside. Throws ConfigError
  /// naming the key(s) for kRefuse with a mismatch, and always for a base value no range can
  /// represent (a log-scaled argument ≤ 0, a ratio of a zero reference).
  /// This space with the entries `dims` (indices) pinned at the base value (SpaceEntry::pinned):
  /// what `scw tune` freezes before the search and reverts after it.
  ParameterSpace WithPinned(const std::vector<int>& dims) const;
  ParameterSpace WithBase(const params::StabilityParams& base, BaseOutsideSpace policy,
                          std::vector<std::string>* notes = nullptr) const;
  /// YAML text of this space (round-trips through FromYamlText).
  std::string ToYaml() const;
  /// The file form of this space.
  SpaceFile ToFile() const;

 private:
  std::string name_;
  std::vector<SpaceEntry> entries_;
};

}  // namespace scw::tuning
