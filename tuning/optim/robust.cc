#include "tuning/optim/robust.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "params/io/write.h"

namespace scw::tuning {

void AddActiveEdges(const NeighbourhoodResult& check, const BatchEvaluator& training,
                    const std::vector<double>& u, std::vector<ActiveEdge>* active) {
  for (const KnifeEdge& e : check.edges) {
    // Held-out edges are never trained on; an edge where the base set aborts too is the plant
    // change's, not the set's.
    if (e.group != "training" || e.base_also_aborts()) continue;
    std::size_t s = 0;
    while (s < training.scenarios().size() && training.scenarios()[s].spec.name != e.scenario) ++s;
    if (s == training.scenarios().size()) continue;
    const Neighbour& n = check.neighbours[static_cast<std::size_t>(e.neighbour)];
    ActiveEdge a;
    a.neighbour = n;
    a.scenario = s;
    if (!n.plant) a.sign = n.u < u[static_cast<std::size_t>(n.dim)] ? -1.0 : 1.0;
    const bool known = std::any_of(active->begin(), active->end(), [&](const ActiveEdge& b) {
      return b.scenario == a.scenario && b.neighbour.key == a.neighbour.key &&
             b.neighbour.change == a.neighbour.change;
    });
    if (!known) active->push_back(std::move(a));
  }
}

namespace {

/// The edges' evaluators: one scenario each (plant edges: with the plant override applied).
std::vector<BatchEvaluator> EdgeEvaluators(const RobustRoundInput& in) {
  std::vector<BatchEvaluator> out;
  for (const ActiveEdge& a : in.active) {
    const ResolvedScenario& sc = in.training->scenarios()[a.scenario];
    if (!a.neighbour.plant) {
      out.emplace_back(std::vector<ResolvedScenario>{sc}, std::vector<double>{1.0},
                       in.training->cost(), in.threads);
      continue;
    }
    ScenarioEntry entry = in.scenarios->training[a.scenario];
    if (a.neighbour.key == "grip.mu") {
      const double factor = a.neighbour.change == "x 0.9" ? 0.9 : 1.1;
      entry.overrides.push_back("grip.mu=" + params::FormatDouble(sc.spec.grip.mu * factor));
      entry.overrides.push_back("plan_with_nominal_grip=true");
    } else {
      for (const auto& o : a.neighbour.overrides) entry.overrides.push_back(o);
    }
    out.push_back(BatchEvaluator::FromEntries({entry}, in.scenarios->base_dir, in.scenarios->cost,
                                              in.threads, {}, in.cache, in.memo));
  }
  return out;
}

}  // namespace

RobustRoundResult RunRobustRound(const RobustRoundInput& in) {
  const ParameterSpace space = in.space->WithPinned(in.pinned);
  std::vector<int> free_dims;
  for (int i = 0; i < space.size(); ++i)
    if (!std::count(in.pinned.begin(), in.pinned.end(), i)) free_dims.push_back(i);
  const std::vector<BatchEvaluator> edges = EdgeEvaluators(in);
  const auto expand = [&](const std::vector<double>& v) {
    std::vector<double> u = in.start;
    for (std::size_t k = 0; k < free_dims.size() && k < v.size(); ++k)
      u[static_cast<std::size_t>(free_dims[k])] = v[k];
    return u;
  };
  // Σ_A J_s at u (the edges' runs) and the merit F there.
  const auto edge_cost = [&](const std::vector<double>& u, int* aborts) {
    double sum = 0.0;
    for (std::size_t k = 0; k < in.active.size(); ++k) {
      const ActiveEdge& a = in.active[k];
      std::vector<double> moved = u;
      if (!a.neighbour.plant) {
        double& ud = moved[static_cast<std::size_t>(a.neighbour.dim)];
        ud = std::clamp(ud + a.sign * in.step, 0.0, 1.0);
      }
      Problems pr;
      const params::StabilityParams p = space.Decode(moved, *in.base, &pr);
      const SetEvaluation e =
          edges[k].Evaluate(pr.empty() ? p : space.Decode(u, *in.base, nullptr));
      sum += e.costs[0].total;
      *aborts += e.runs[0].aborted();
    }
    return sum;
  };
  int start_aborts = 0;
  const double start_edges = edge_cost(in.start, &start_aborts);
  const Objective f = [&](const std::vector<double>& v) {
    const std::vector<double> u = expand(v);
    Problems pr;
    const params::StabilityParams p = space.Decode(u, *in.base, &pr);
    Evaluation ev;
    if (!pr.empty()) {
      ev.cost = 1e9;
      ev.status = "infeasible: " + pr.items()[0].path;
      return ev;
    }
    const ObjectiveValue value = in.objective->Of(in.training->Evaluate(p));
    int aborts = 0;
    const double edge = edge_cost(u, &aborts);
    ev.cost = value.merit + edge + (value.within_budget() ? 0.0 : start_edges);
    ev.status = std::to_string(aborts) + " of " + std::to_string(in.active.size()) +
                " edge runs abort" + (value.within_budget() ? "" : "; over budget");
    ev.columns = {params::FormatDouble(value.merit), params::FormatDouble(edge)};
    return ev;
  };
  TunerOptions to;
  to.algorithm = "sbplx";
  to.max_evals = std::max(1, in.evaluations);
  to.seed = in.seed;
  to.initial_step = in.step;
  to.log_path = in.log;
  to.log_extra_header = {"merit", "edge_cost"};
  for (int i : free_dims)
    to.dimension_names.push_back("u:" + space.entries()[static_cast<std::size_t>(i)].Label());
  to.stop = in.stop;
  to.failure_cost = 1e9;
  to.on_progress = in.on_progress;
  std::vector<double> v0;
  for (int i : free_dims) v0.push_back(in.start[static_cast<std::size_t>(i)]);
  RobustRoundResult r;
  if (v0.empty()) {
    r.best = in.start;
    return r;
  }
  r.search = Tune(v0, f, to);
  r.best = expand(r.search.best_u);
  r.start_merit = r.search.start_cost;
  r.best_merit = r.search.best_cost;
  return r;
}

}  // namespace scw::tuning
