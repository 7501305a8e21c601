#include "tuning/optim/sensitivity.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <type_traits>

#include "params/io/csv.h"
#include "params/io/write.h"
#include "tuning/optim/comparison.h"
#include "tuning/sim/run_summary.h"

namespace scw::tuning {
namespace {

using params::StabilityParams;

/// Extra share of a resolution step: keeps a "one step" value change at or above one step after
/// round-off, where Decode would otherwise snap it back to the base value.
constexpr double kStepMargin = 1e-6;

struct FieldView {
  const double* scalar = nullptr;
  const std::vector<double>* array = nullptr;
  double resolution = 0.0;
};

FieldView Find(const StabilityParams& p, const std::string& key) {
  FieldView out;
  params::ForEachField(p, [&](const std::string& path, const auto& value, const params::Meta& m) {
    using T = std::decay_t<decltype(value)>;
    if (path != key) return;
    if constexpr (std::is_same_v<T, double>) out = {&value, nullptr, m.resolution};
    if constexpr (std::is_same_v<T, std::vector<double>>) out = {nullptr, &value, m.resolution};
  });
  return out;
}

/// The element `index` of a field, its scalar, or (index < 0 on an array) its smallest element,
/// as the space's transforms read a reference; NaN when there is none.
double ValueOf(const FieldView& f, int index) {
  if (f.scalar) return *f.scalar;
  if (!f.array || f.array->empty() || index >= static_cast<int>(f.array->size()))
    return std::numeric_limits<double>::quiet_NaN();
  if (index >= 0) return (*f.array)[static_cast<std::size_t>(index)];
  return *std::min_element(f.array->begin(), f.array->end());
}

/// Every field's value as text (shortest round-trip numbers): equal text = equal bits (but for
/// the sign of zero, which the sets compared here do not differ in).
std::string Fingerprint(const StabilityParams& p) {
  std::string out;
  params::ForEachField(p, [&](const std::string&, const auto& value, const params::Meta&) {
    out += params::detail::RenderValue(value);
    out += '\n';
  });
  return out;
}

/// The unit-cube coordinate of argument x (the inverse of the space's map; clamped to [0, 1]).
double Coordinate(const SpaceEntry& e, double x) {
  x = std::clamp(x, e.lo, e.hi);
  const double u = e.scale == params::Scale::kLog ? std::log(x / e.lo) / std::log(e.hi / e.lo)
                                                  : (x - e.lo) / (e.hi - e.lo);
  return std::clamp(std::isfinite(u) ? u : 0.5, 0.0, 1.0);
}

/// What PerturbedPoint::value shows: the entry's own decoded value, or the factor of a scaled
/// array.
double ShownValue(const SpaceEntry& e, const StabilityParams& p, double x) {
  if (e.transform == Transform::kScaleArray) return x;
  return ValueOf(Find(p, e.key), e.index);
}

const char* SubsystemOf(const std::string& key) {
  const auto starts = [&](const char* prefix) { return key.rfind(prefix, 0) == 0; };
  if (starts("ESC.")) return "ESC";
  if (starts("countersteer_system.")) return "CS";
  if (starts("SlipControl.ABS.")) return "ABS";
  if (starts("SlipControl.TC.")) return "TC";
  return "";
}

int Activations(const std::string& subsystem, const std::vector<RunMetrics>& runs) {
  if (subsystem.empty()) return -1;
  int n = 0;
  for (const auto& m : runs) {
    if (subsystem == "ESC") n += m.esc_count;
    if (subsystem == "CS") n += m.cs_count;
    if (subsystem == "ABS") n += m.abs_count;
    if (subsystem == "TC") n += m.tc_count;
  }
  return n;
}

std::string Printf(const char* fmt, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, x);
  return buf;
}

/// A cost change for a table: exact 0 as "0", else three significant digits.
std::string Change(double x) { return x == 0.0 ? "0" : Printf("%.3g", x); }

std::string Shown(Transform t, double v) {
  return t == Transform::kScaleArray ? "×" + Printf("%.6g", v) : params::FormatNumber(v);
}

}  // namespace

const char* SensitivityPerturbationName(int k) {
  static constexpr const char* kNames[] = {"-10 %", "-1 step", "+1 step", "+10 %"};
  return k >= 0 && k < kSensitivityPerturbations ? kNames[k] : "?";
}

const char* PerturbationKindName(PerturbationKind k) {
  switch (k) {
    case PerturbationKind::kEvaluated:
      return "evaluated";
    case PerturbationKind::kDuplicate:
      return "duplicate";
    case PerturbationKind::kAtBound:
      return "at bound";
    case PerturbationKind::kNoOp:
      return "no-op";
    case PerturbationKind::kInfeasible:
      return "infeasible";
  }
  return "?";
}

SensitivityPlan PlanSensitivity(const ParameterSpace& space, const std::vector<double>& u_centre,
                                const StabilityParams& base, SensitivityMode mode) {
  SensitivityPlan plan;
  plan.mode = mode;
  const bool range = mode == SensitivityMode::kRange;
  const StabilityParams centre = space.Decode(u_centre, base, nullptr);
  plan.sets.push_back(centre);
  std::map<std::string, int> seen = {{Fingerprint(centre), 0}};
  std::vector<std::string> set_names = {"the centre"};
  plan.x_centre = space.Arguments(u_centre);
  const auto& entries = space.entries();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const SpaceEntry& e = entries[i];
    const double xc = plan.x_centre[i];
    const FieldView f = Find(centre, e.key);
    // One resolution step of the value, in argument units.
    double step = f.resolution;
    if (e.transform == Transform::kRatio) {
      const double ref = std::abs(ValueOf(Find(centre, e.of), e.of_index));
      step = ref > 0 && std::isfinite(ref) ? step / ref : 0.0;
    } else if (e.transform == Transform::kScaleArray) {
      // Decode scales the BASE array: one step of its largest element.
      const FieldView b = Find(base, e.key);
      double largest = 0.0;
      if (b.array)
        for (double v : *b.array) largest = std::max(largest, std::abs(v));
      step = largest > 0 ? step / largest : 0.0;
    }
    step = std::isfinite(step) && step > 0 ? step * (1.0 + kStepMargin) : 0.0;
    plan.labels.push_back(e.Label());
    plan.step.push_back(step);
    plan.value_centre.push_back(ShownValue(e, centre, xc));
    const double rel = kSensitivityRelative * std::abs(xc);
    std::array<double, kSensitivityPerturbations> moves = {-rel, -step, step, rel};
    if (range) moves = {e.lo - xc, 0.0, 0.0, e.hi - xc};
    std::array<PerturbedPoint, kSensitivityPerturbations> points;
    for (int k = 0; k < kSensitivityPerturbations; ++k) {
      PerturbedPoint& pt = points[static_cast<std::size_t>(k)];
      pt.x = xc;
      pt.value = plan.value_centre.back();
      const double move = moves[static_cast<std::size_t>(k)];
      if (move == 0.0) {
        pt.kind =
            range && (k == 0 || k == 3) ? PerturbationKind::kAtBound : PerturbationKind::kNoOp;
        if (range)
          pt.note = k == 0 || k == 3 ? "at the end of the range" : "range ends only";
        else
          pt.note = k == 0 || k == 3 ? "10 % of 0" : "no resolution step";
        continue;
      }
      const double target = xc + move;
      const bool clamped = target < e.lo || target > e.hi;
      std::vector<double> u = u_centre;
      u.resize(entries.size(), 0.5);
      u[i] = Coordinate(e, target);
      if (u[i] == u_centre[i]) {
        pt.kind = clamped ? PerturbationKind::kAtBound : PerturbationKind::kNoOp;
        pt.note = clamped ? (move > 0 ? "at the upper bound" : "at the lower bound")
                          : "below the coordinate resolution";
        continue;
      }
      Problems problems;
      StabilityParams p = space.Decode(u, base, &problems);
      // The range screen asks whether the parameter can reach the runs at all: an end that breaks
      // a schema rule (an ordering with keys outside the space) is approached instead, halving
      // the move until the set is valid.
      for (int halve = 0; range && !problems.empty() && halve < 8; ++halve) {
        const double closer = xc + (space.Arguments(u)[i] - xc) / 2.0;
        u[i] = Coordinate(e, closer);
        if (u[i] == u_centre[i]) break;
        problems = Problems();
        p = space.Decode(u, base, &problems);
      }
      pt.x = space.Arguments(u)[i];
      pt.value = ShownValue(e, p, pt.x);
      if (!problems.empty()) {
        pt.kind = PerturbationKind::kInfeasible;
        pt.note = problems.items()[0].path + ": " + problems.items()[0].message;
        continue;
      }
      const std::string name = e.Label() + " " + SensitivityPerturbationName(k);
      const auto [it, fresh] = seen.emplace(Fingerprint(p), static_cast<int>(plan.sets.size()));
      pt.set = it->second;
      if (fresh) {
        pt.kind = PerturbationKind::kEvaluated;
        plan.sets.push_back(p);
        set_names.push_back(name);
      } else if (it->second == 0) {
        // Clamped to the bound and quantised back: the range leaves no room for the move.
        pt.kind = clamped ? PerturbationKind::kAtBound : PerturbationKind::kNoOp;
        pt.note = clamped ? "clamped to the bound, quantised to the centre value"
                          : "quantised to the centre value";
      } else {
        pt.kind = PerturbationKind::kDuplicate;
        pt.note = "the same set as " + set_names[static_cast<std::size_t>(it->second)];
      }
    }
    plan.points.push_back(points);
  }
  return plan;
}

std::vector<std::string> SensitivityResult::NotExercised() const {
  std::vector<std::string> out;
  for (const auto& d : dimensions)
    if (!d.exercised) out.push_back(d.label);
  return out;
}

SensitivityResult ComputeSensitivity(const BatchEvaluator& ev, const ParameterSpace& space,
                                     const std::vector<double>& u_centre,
                                     const StabilityParams& base, const BatchProgress& progress,
                                     SensitivityMode mode) {
  return EvaluateSensitivity(ev, space, PlanSensitivity(space, u_centre, base, mode), progress);
}

SensitivityResult EvaluateSensitivity(const BatchEvaluator& ev, const ParameterSpace& space,
                                      const SensitivityPlan& plan, const BatchProgress& progress) {
  const std::vector<SetEvaluation> res = ev.Evaluate(plan.sets, progress);
  SensitivityResult r;
  r.sets = static_cast<int>(plan.sets.size());
  const std::size_t n_sc = ev.scenarios().size();
  for (const auto& sc : ev.scenarios()) r.scenarios.push_back(sc.spec.name);
  r.centre_runs = res[0].runs;
  for (const auto& c : res[0].costs) r.centre_costs.push_back(c.total);
  for (const auto& m : r.centre_runs) (m.aborted() ? r.aborted : r.completed) += 1;
  // Bit-level change of a run: its cost, or any metric in the run summary's round-trip text.
  std::vector<std::vector<std::string>> summaries(res.size());
  const auto summary = [&](std::size_t set, std::size_t s) -> const std::string& {
    if (summaries[set].empty())
      for (const auto& m : res[set].runs) summaries[set].push_back(RunSummaryYaml("", m));
    return summaries[set][s];
  };
  const auto& entries = space.entries();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    DimensionSensitivity d;
    d.label = plan.labels[i];
    d.transform = entries[i].transform;
    d.subsystem = SubsystemOf(entries[i].key);
    d.subsystem_activations = Activations(d.subsystem, r.centre_runs);
    d.x_centre = plan.x_centre[i];
    d.value_centre = plan.value_centre[i];
    d.step = plan.step[i];
    d.points = plan.points[i];
    d.delta.assign(n_sc, {});
    d.max_abs_delta.assign(n_sc, 0.0);
    d.changed.assign(n_sc, false);
    bool any_set = false;
    for (int k = 0; k < kSensitivityPerturbations; ++k) {
      const PerturbedPoint& pt = d.points[static_cast<std::size_t>(k)];
      if (pt.kind != PerturbationKind::kEvaluated && pt.kind != PerturbationKind::kDuplicate)
        continue;
      any_set = true;
      const auto set = static_cast<std::size_t>(pt.set);
      for (std::size_t s = 0; s < n_sc; ++s) {
        const double dj = res[set].costs[s].total - r.centre_costs[s];
        d.delta[s][static_cast<std::size_t>(k)] = dj;
        d.max_abs_delta[s] = std::max(d.max_abs_delta[s], std::abs(dj));
        if (res[set].costs[s].total != r.centre_costs[s] || summary(set, s) != summary(0, s))
          d.changed[s] = true;
      }
    }
    bool noticeable = false;
    for (std::size_t s = 0; s < n_sc; ++s) {
      d.exercised = d.exercised || d.changed[s];
      noticeable = noticeable || d.max_abs_delta[s] >= kDefaultResolution;
      double& cls =
          r.centre_runs[s].aborted() ? d.max_abs_delta_aborted : d.max_abs_delta_completed;
      cls = std::max(cls, d.max_abs_delta[s]);
    }
    d.below_noise = d.exercised && !noticeable;
    if (!d.exercised) {
      if (!any_set)
        d.reason = "no perturbation changes the set";
      else if (d.subsystem_activations == 0)
        d.reason = d.subsystem + " never acted in the centre runs";
      else if (d.subsystem_activations > 0)
        d.reason = "no run changes, although " + d.subsystem + " acts";
      else
        d.reason = "no run changes";
    }
    r.dimensions.push_back(std::move(d));
  }
  return r;
}

std::string SensitivityMarkdown(const SensitivityResult& r, const std::string& point, int level) {
  const std::string h(static_cast<std::size_t>(std::max(1, level)), '#');
  std::string md = h + " Parameter sensitivity\n\n";
  md += "One parameter of the search space at a time, around " + point +
        ", on the training scenarios: its argument moved by -10 %, -1 resolution step, +1 step "
        "and +10 % (clamped to its range), " +
        std::to_string(r.sets) + " distinct sets × " + std::to_string(r.scenarios.size()) +
        " scenarios in one batch. ΔJ is the change of a scenario's cost [s]; scenarios are "
        "classed by how their run at " +
        point +
        " ended. A parameter is **exercised** when some perturbation changes some scenario's "
        "cost or any run metric at all (bit for bit); *below resolution*: no change reaches "
        "0.02 s (two 100 Hz controller steps).\n\n";
  md += "| parameter | value | perturbed: -10 % / -1 step / +1 step / +10 % | acts";
  if (r.completed > 0) md += " | max abs ΔJ completed (" + std::to_string(r.completed) + ") [s]";
  if (r.aborted > 0) md += " | max abs ΔJ aborted (" + std::to_string(r.aborted) + ") [s]";
  md += " | verdict |\n| --- | --- | --- | ---";
  if (r.completed > 0) md += " | ---";
  if (r.aborted > 0) md += " | ---";
  md += " | --- |\n";
  for (const auto& d : r.dimensions) {
    std::string steps;
    for (int k = 0; k < kSensitivityPerturbations; ++k) {
      const PerturbedPoint& pt = d.points[static_cast<std::size_t>(k)];
      std::string cell = "=";
      if (pt.kind == PerturbationKind::kEvaluated || pt.kind == PerturbationKind::kDuplicate)
        cell = Shown(d.transform, pt.value);
      else if (pt.kind == PerturbationKind::kAtBound)
        cell = "bound";
      else if (pt.kind == PerturbationKind::kInfeasible)
        cell = "infeasible";
      steps += (k ? " / " : "") + cell;
    }
    md += "| " + d.label + " | " + Shown(d.transform, d.value_centre) + " | " + steps + " | " +
          (d.subsystem.empty() ? std::string("-")
                               : d.subsystem + " " + std::to_string(d.subsystem_activations));
    if (r.completed > 0) md += " | " + Change(d.max_abs_delta_completed);
    if (r.aborted > 0) md += " | " + Change(d.max_abs_delta_aborted);
    std::string verdict;
    if (d.exercised) {
      verdict = "exercised";
      bool cost_moved = false;
      for (double m : d.max_abs_delta) cost_moved = cost_moved || m != 0.0;
      if (!cost_moved)
        verdict += " (only run metrics change)";
      else if (d.below_noise)
        verdict += " (below resolution)";
    } else {
      verdict = "**not exercised by this scenario set**";
      if (!d.reason.empty()) verdict += " (" + d.reason + ")";
    }
    md += " | " + verdict + " |\n";
  }
  md +=
      "\nvalue: the parameter's value at " + point +
      " (a scaled array: its factor on the base array, ×1 = the base array); perturbed: the "
      "value (factor) each perturbation ran with — `=` decodes to the centre set (quantised back, "
      "or 10 % of 0), `bound` the argument already sits at that end of its range; acts: the "
      "subsystem the parameter belongs to and its activations in the runs at " +
      point + ".\n\n";
  const std::vector<std::string> idle = r.NotExercised();
  if (idle.empty()) {
    md += "Every parameter of the search space is exercised by this scenario set.\n\n";
  } else {
    md += "**" + std::to_string(idle.size()) + " of " + std::to_string(r.dimensions.size()) +
          " parameters not exercised by this scenario set:** ";
    for (std::size_t i = 0; i < idle.size(); ++i) md += (i ? ", " : "") + idle[i];
    md +=
        ". The cost cannot see them: a tune leaves them wherever the optimiser happens to stop, "
        "so their tuned values say nothing; add a scenario in which they act, or leave them out "
        "of the search space.\n\n";
  }
  md += "max abs ΔJ per scenario [s]:\n\n| parameter";
  for (std::size_t s = 0; s < r.scenarios.size(); ++s)
    md += " | " + r.scenarios[s] + (r.centre_runs[s].aborted() ? " (aborted)" : "");
  md += " |\n| ---";
  for (std::size_t s = 0; s < r.scenarios.size(); ++s) md += " | ---";
  md += " |\n";
  for (const auto& d : r.dimensions) {
    md += "| " + d.label;
    for (std::size_t s = 0; s < r.scenarios.size(); ++s) md += " | " + Change(d.max_abs_delta[s]);
    md += " |\n";
  }
  return md + "\n";
}

std::string SensitivityCsv(const SensitivityResult& r) {
  std::string out = "dimension,perturbation,kind,x,value,scenario,class,delta_cost,exercised\n";
  for (const auto& d : r.dimensions)
    for (int k = 0; k < kSensitivityPerturbations; ++k) {
      const PerturbedPoint& pt = d.points[static_cast<std::size_t>(k)];
      const bool ran =
          pt.kind == PerturbationKind::kEvaluated || pt.kind == PerturbationKind::kDuplicate;
      for (std::size_t s = 0; s < r.scenarios.size(); ++s)
        out += io::CsvField(d.label) + "," + io::CsvField(SensitivityPerturbationName(k)) + "," +
               io::CsvField(PerturbationKindName(pt.kind)) + "," + params::FormatDouble(pt.x) +
               "," + params::FormatDouble(pt.value) + "," + io::CsvField(r.scenarios[s]) + "," +
               (r.centre_runs[s].aborted() ? "aborted" : "completed") + "," +
               (ran ? params::FormatDouble(d.delta[s][static_cast<std::size_t>(k)])
                    : std::string("nan")) +
               "," + (d.exercised ? "true" : "false") + "\n";
    }
  return out;
}

}  // namespace scw::tuning
