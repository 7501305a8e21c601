#include "tuning/optim/neighbourhood.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <type_traits>

#include "params/io/write.h"
#include "tuning/sim/run_summary.h"

namespace scw::tuning {
namespace {

/// A plant unknown at one bound: the override of every scenario.
struct PlantBound {
  const char* key;
  const char* value;  ///< the override's value ("" for grip: a factor on the scenario's mu)
  double factor;      ///< grip only
  const char* change;
};

// The bounds the built-in robust set draws the plant's unknowns from (robust_set.yaml).
constexpr PlantBound kPlantBounds[] = {
    {"plant.brake_dead_time", "0.04", 0.0, "0.040 s"},
    {"plant.brake_dead_time", "0.116", 0.0, "0.116 s"},
    {"plant.steering_delay", "0.0", 0.0, "0 s"},
    {"plant.steering_delay", "0.06", 0.0, "0.060 s"},
    {"grip.mu", "", 0.9, "x 0.9"},
    {"grip.mu", "", 1.1, "x 1.1"},
    {"plant.rear_tire_falloff", "0.5", 0.0, "0.5"},
    {"plant.rear_tire_falloff", "1.5", 0.0, "1.5"},
    {"plant.yaw_inertia_scale", "0.8", 0.0, "0.8"},
    {"plant.yaw_inertia_scale", "1.2", 0.0, "1.2"},
};

/// The value of the key of space entry `e` in `p`, as text.
std::string EntryValue(const SpaceEntry& e, params::StabilityParams p) {
  std::string out;
  params::ForEachField(p, [&](const std::string& path, auto& value, const params::Meta&) {
    if (path != e.key) return;
    using T = std::decay_t<decltype(value)>;
    if constexpr (std::is_same_v<T, double>) out = params::FormatNumber(value);
    if constexpr (std::is_same_v<T, std::vector<double>>) {
      if (e.index >= 0 && e.index < static_cast<int>(value.size())) {
        out = params::FormatNumber(value[static_cast<std::size_t>(e.index)]);
        return;
      }
      out = "[";
      for (std::size_t i = 0; i < value.size(); ++i)
        out += (i ? ", " : "") + params::FormatNumber(value[i]);
      out += "]";
    }
  });
  return out;
}

/// Whether grip may be scaled in the car alone: the scenario plans with nominal grip anyway, or
/// its grip factors are all 1 (then planning with nominal grip plans the same line).
bool GripScalable(const params::ScenarioParams& s) {
  if (s.plan_with_nominal_grip) return true;
  const params::GripParams& g = s.grip;
  bool ones = g.mu == 1.0 && g.front_mu_x == 1.0 && g.front_mu_y == 1.0 && g.rear_mu_x == 1.0 &&
              g.rear_mu_y == 1.0;
  for (double w : g.wheel_mu_x) ones = ones && w == 1.0;
  for (double w : g.wheel_mu_y) ones = ones && w == 1.0;
  return ones;
}

/// The entries of a group with a plant bound applied (entries it cannot apply to are dropped and
/// their indices returned in `kept`).
std::vector<ScenarioEntry> WithBound(const std::vector<ScenarioEntry>& entries,
                                     const BatchEvaluator& resolved, const PlantBound& b,
                                     std::vector<std::size_t>* kept,
                                     std::vector<std::string>* skipped) {
  std::vector<ScenarioEntry> out;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const params::ScenarioParams& spec = resolved.scenarios()[i].spec;
    if (spec.kind == "maneuver") continue;  // no track, no plan: the maneuvers test other things
    ScenarioEntry e = entries[i];
    if (b.factor > 0.0) {
      if (!GripScalable(spec)) {
        skipped->push_back(e.name);
        continue;
      }
      e.overrides.push_back("grip.mu=" + params::FormatDouble(spec.grip.mu * b.factor));
      e.overrides.push_back("plan_with_nominal_grip=true");
    } else {
      e.overrides.push_back(std::string(b.key) + "=" + b.value);
    }
    out.push_back(std::move(e));
    kept->push_back(i);
  }
  return out;
}

}  // namespace

std::vector<std::string> NeighbourhoodResult::EdgeKeys() const {
  std::vector<std::string> out;
  for (const auto& e : edges) {
    const std::string& k = neighbours[static_cast<std::size_t>(e.neighbour)].key;
    if (std::find(out.begin(), out.end(), k) == out.end()) out.push_back(k);
  }
  return out;
}

std::vector<Neighbour> PlanNeighbourhood(const NeighbourhoodInput& in,
                                         std::vector<std::string>* notes) {
  std::vector<Neighbour> out;
  const ParameterSpace pinned = in.space->WithPinned(in.pinned);
  const params::StabilityParams centre = pinned.Decode(in.u, *in.base, nullptr);
  for (int d = 0; d < in.space->size(); ++d) {
    if (std::count(in.pinned.begin(), in.pinned.end(), d)) continue;
    std::vector<int> with_d = in.pinned;
    with_d.push_back(d);
    if (params::DifferingKeys(in.space->WithPinned(with_d).Decode(in.u, *in.base, nullptr), centre)
            .empty())
      continue;  // the key is at its base value: not a changed key
    const SpaceEntry& e = in.space->entries()[static_cast<std::size_t>(d)];
    for (const double sign : {-1.0, 1.0}) {
      std::vector<double> v = in.u;
      const double ud = std::clamp(in.u[static_cast<std::size_t>(d)] + sign * in.step, 0.0, 1.0);
      v[static_cast<std::size_t>(d)] = ud;
      const std::string change =
          std::string(sign < 0 ? "-" : "+") + params::FormatNumber(100.0 * in.step) + " % of range";
      Problems pr;
      const params::StabilityParams p = pinned.Decode(v, *in.base, &pr);
      if (!pr.empty()) {
        notes->push_back(e.Label() + " " + change + ": breaks " + pr.items()[0].path);
        continue;
      }
      if (params::DifferingKeys(p, centre).empty()) continue;  // at the bound already
      Neighbour n;
      n.key = e.Label();
      n.change = change;
      n.value = EntryValue(e, p) + " (from " + EntryValue(e, centre) + ")";
      n.dim = d;
      n.u = ud;
      out.push_back(std::move(n));
    }
  }
  if (!in.plant) return out;
  for (const PlantBound& b : kPlantBounds) {
    Neighbour n;
    n.plant = true;
    n.key = b.key;
    n.change = b.change;
    n.value = b.change;
    if (b.factor == 0.0) n.overrides = {std::string(b.key) + "=" + b.value};
    out.push_back(std::move(n));
  }
  return out;
}

NeighbourhoodResult CheckNeighbourhood(const NeighbourhoodInput& in,
                                       const BatchProgress& progress) {
  NeighbourhoodResult r;
  r.step = in.step;
  r.neighbours = PlanNeighbourhood(in, &r.notes);
  r.held.assign(r.neighbours.size(), 0);
  const ParameterSpace pinned = in.space->WithPinned(in.pinned);
  struct Group {
    const char* name;
    const BatchEvaluator* ev;
    const SetEvaluation* centre;
    const std::vector<ScenarioEntry>* entries;
  };
  std::vector<Group> groups = {
      {"training", in.training, in.training_centre, &in.scenarios->training}};
  if (in.held_out && in.held_out_centre)
    groups.push_back({"held-out", in.held_out, in.held_out_centre, &in.scenarios->held_out});
  // The run count, for the progress.
  std::vector<params::StabilityParams> key_sets;
  std::vector<std::size_t> key_at;
  for (std::size_t k = 0; k < r.neighbours.size(); ++k) {
    if (r.neighbours[k].plant) continue;
    std::vector<double> v = in.u;
    v[static_cast<std::size_t>(r.neighbours[k].dim)] = r.neighbours[k].u;
    key_sets.push_back(pinned.Decode(v, *in.base, nullptr));
    key_at.push_back(k);
  }
  const std::size_t n_plant = r.neighbours.size() - key_sets.size();
  int total = 0;
  for (const auto& g : groups)
    total += static_cast<int>((key_sets.size() + n_plant) * g.ev->scenarios().size());
  // The plant neighbours' runs count once per set (the reference runs in the same batch).
  if (in.reference)
    for (const auto& g : groups) total += static_cast<int>(n_plant * g.ev->scenarios().size());
  int done = 0;
  const auto count = [&](int n) {
    return [&progress, &done, total, n](int d, int) {
      if (progress) progress(done + d, total);
      (void)n;
    };
  };
  const params::StabilityParams centre = pinned.Decode(in.u, *in.base, nullptr);
  const auto note_runs = [&r](std::size_t nb, const std::string& group,
                              const std::vector<std::size_t>& at, const SetEvaluation& centre_eval,
                              const SetEvaluation& moved, const BatchEvaluator& names) {
    for (std::size_t j = 0; j < at.size(); ++j) {
      const RunMetrics& c = centre_eval.runs[at[j]];
      const RunMetrics& m = moved.runs[j];
      if (c.aborted()) continue;
      if (!m.aborted()) {
        ++r.held[nb];
        continue;
      }
      KnifeEdge e;
      e.neighbour = static_cast<int>(nb);
      e.group = group;
      e.scenario = names.scenarios()[at[j]].spec.name;
      e.centre = c;
      e.moved = m;
      r.edges.push_back(std::move(e));
    }
  };
  for (const auto& g : groups) {
    const std::size_t n = g.ev->scenarios().size();
    std::vector<std::size_t> all(n);
    for (std::size_t i = 0; i < n; ++i) all[i] = i;
    if (!key_sets.empty()) {
      const int runs = static_cast<int>(key_sets.size() * n);
      const auto results = g.ev->Evaluate(key_sets, count(runs));
      done += runs;
      r.runs += runs;
      for (std::size_t k = 0; k < key_sets.size(); ++k)
        note_runs(key_at[k], g.name, all, *g.centre, results[k], *g.ev);
    }
    for (std::size_t k = 0; k < r.neighbours.size(); ++k) {
      if (!r.neighbours[k].plant) continue;
      const PlantBound* bound = nullptr;
      for (const PlantBound& b : kPlantBounds)
        if (r.neighbours[k].key == b.key && r.neighbours[k].change == b.change) bound = &b;
      std::vector<std::size_t> kept;
      std::vector<std::string> skipped;
      const std::vector<ScenarioEntry> entries =
          WithBound(*g.entries, *g.ev, *bound, &kept, &skipped);
      for (const auto& s : skipped)
        r.notes.push_back(std::string(bound->key) + " " + bound->change + " not applied to " + s +
                          " (it plans with reduced grip)");
      if (entries.empty()) {
        done += static_cast<int>(n * (in.reference ? 2 : 1));
        continue;
      }
      const BatchEvaluator moved = BatchEvaluator::FromEntries(
          entries, in.scenarios->base_dir, in.scenarios->cost, in.threads, {}, in.cache, in.memo);
      std::vector<params::StabilityParams> sets = {centre};
      if (in.reference) sets.push_back(*in.reference);
      const auto results = moved.Evaluate(sets, count(static_cast<int>(entries.size())));
      done += static_cast<int>(n * sets.size());
      r.runs += static_cast<int>(entries.size() * sets.size());
      const std::size_t first = r.edges.size();
      note_runs(k, g.name, kept, *g.centre, results[0], *g.ev);
      if (in.reference)
        for (std::size_t i = first; i < r.edges.size(); ++i)
          for (std::size_t j = 0; j < kept.size(); ++j)
            if (g.ev->scenarios()[kept[j]].spec.name == r.edges[i].scenario) {
              r.edges[i].base_run = true;
              r.edges[i].base_moved = results[1].runs[j];
            }
    }
  }
  return r;
}

namespace {
std::string Outcome(const RunMetrics& m) {
  if (!m.aborted()) {
    const double lap = m.MeanLapTime();
    return std::isfinite(lap) ? "completed, " + FormatFixed(lap, 3) + " s"
                              : std::string("completed");
  }
  return std::string(RunStatusName(m.status)) + " at " + FormatFixed(100.0 * m.Progress(), 0) +
         " %";
}
}  // namespace

std::string NeighbourhoodMarkdown(const NeighbourhoodResult& r, int level) {
  const std::string h(static_cast<std::size_t>(level), '#');
  int keys = 0, plant = 0;
  for (const auto& n : r.neighbours) (n.plant ? plant : keys)++;
  std::string out = h + " Knife edges\n\n";
  out += "The exported set moved a little: each changed key alone by ±" +
         params::FormatNumber(100.0 * r.step) +
         " % of its range, and the plant's unknowns to the bounds the robust set draws them "
         "from; " +
         std::to_string(keys) + " key and " + std::to_string(plant) + " plant neighbours, " +
         std::to_string(r.runs) + " runs on the training and held-out scenarios.\n\n";
  if (r.edges.empty()) {
    out += "**No knife edge**: every run the set completes also completes at every neighbour.\n";
  } else {
    const auto keys_hit = r.EdgeKeys();
    const int own = OwnEdges(r);
    out += "**" + std::to_string(r.edges.size()) + " knife edge(s)** on " +
           std::to_string(keys_hit.size()) +
           " key(s) or unknown(s): a run the set completes aborts after the small change; " +
           std::to_string(static_cast<int>(r.edges.size()) - own) +
           " of them at a plant neighbour where the base set aborts too (the plant change loses "
           "the car, whatever the set), " +
           std::to_string(own) + " the set's own.\n\n";
    out +=
        "| change | value | group | scenario | the set | after the change | base set after it |\n"
        "| --- | --- | --- | --- | --- | --- | --- |\n";
    for (const auto& e : r.edges) {
      const Neighbour& n = r.neighbours[static_cast<std::size_t>(e.neighbour)];
      out += "| " + n.key + " " + n.change + " | " + n.value + " | " + e.group + " | " +
             e.scenario + " | " + Outcome(e.centre) + " | " + Outcome(e.moved) + " | " +
             (e.base_run ? Outcome(e.base_moved) : std::string("-")) + " |\n";
    }
  }
  if (!r.notes.empty()) {
    out += "\nLeft out:\n";
    for (const auto& note : r.notes) out += "- " + note + "\n";
  }
  return out + "\n";
}

int OwnEdges(const NeighbourhoodResult& r) {
  int n = 0;
  for (const auto& e : r.edges) n += !e.base_also_aborts();
  return n;
}

std::string NeighbourhoodWarning(const NeighbourhoodResult& r) {
  if (r.edges.empty()) return "";
  const int own = OwnEdges(r);
  std::string out = "WARNING: " + std::to_string(r.edges.size()) +
                    " knife edge(s): a small change turns a completed run into an abort (" +
                    std::to_string(own) + " the tuned set's own; the others abort with the base " +
                    "set at the same plant change too):\n";
  for (const auto& e : r.edges) {
    const Neighbour& n = r.neighbours[static_cast<std::size_t>(e.neighbour)];
    out += "  " + n.key + " " + n.change + ": " + e.scenario + " (" + e.group + ") " +
           RunStatusName(e.moved.status) +
           (e.base_also_aborts() ? " (base set: aborts too)"
            : e.base_run         ? " (base set: completes)"
                                 : "") +
           "\n";
  }
  return out;
}

}  // namespace scw::tuning
