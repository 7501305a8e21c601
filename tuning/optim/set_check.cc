#include "tuning/optim/set_check.h"

#include <cmath>
#include <cstdio>
#include <utility>

#include "tuning/optim/cost.h"
#include "tuning/sim/scenario.h"

namespace scw::tuning {

params::StabilityParams WithoutSubsystem(params::StabilityParams p, std::size_t k) {
  params::SubsystemSwitches sw;  // all on
  bool* const off[] = {&sw.esc, &sw.cs, &sw.abs, &sw.tc};
  *off[k < 4 ? k : 3] = false;
  return ApplySubsystemSwitches(std::move(p), sw);
}

SetCheck CheckSet(const BatchEvaluator& ev, const params::StabilityParams& base,
                  double decide_fraction, const BatchProgress& progress) {
  std::vector<params::StabilityParams> sets = {base};
  for (std::size_t k = 0; k < 4; ++k) sets.push_back(WithoutSubsystem(base, k));
  const std::vector<SetEvaluation> res = ev.Evaluate(sets, progress);
  SetCheck c;
  for (std::size_t i = 0; i < ev.scenarios().size(); ++i) {
    ScenarioCheck s;
    s.name = ev.scenarios()[i].spec.name;
    s.base = res[0].runs[i];
    s.base_cost = res[0].costs[i].total;
    s.activations = {s.base.esc_count, s.base.cs_count, s.base.abs_count, s.base.tc_count};
    for (std::size_t k = 0; k < 4; ++k) {
      const RunMetrics& off = res[k + 1].runs[i];
      s.cost_off[k] = res[k + 1].costs[i].total;
      s.status_off[k] = RunStatusName(off.status);
      const bool outcome = off.aborted() != s.base.aborted();
      const double rel = std::abs(s.cost_off[k] - s.base_cost) / std::max(1e-9, s.base_cost);
      s.decides[k] = outcome || rel >= decide_fraction;
      c.acting[k] += s.activations[k] > 0;
      c.deciding[k] += s.decides[k];
    }
    c.scenarios.push_back(std::move(s));
  }
  return c;
}

namespace {
std::string Num(const char* fmt, double x) {
  char buf[48];
  std::snprintf(buf, sizeof buf, fmt, x);
  return buf;
}
}  // namespace

std::string SetCheckMarkdown(const std::string& group, const SetCheck& c, bool training) {
  std::string md = "### " + group + "\n\n";
  md += "| scenario | status | cost | ESC | CS | ABS | TC | decided by (cost with it off) |\n";
  md += "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const auto& s : c.scenarios) {
    std::string decided;
    for (std::size_t k = 0; k < 4; ++k)
      if (s.decides[k])
        decided += std::string(decided.empty() ? "" : ", ") + kCheckedSubsystems[k] + " (" +
                   Num("%.3f", s.cost_off[k]) +
                   (s.status_off[k] != RunStatusName(s.base.status) ? ", " + s.status_off[k] : "") +
                   ")";
    md += "| " + s.name + " | " + RunStatusName(s.base.status) + " | " + Num("%.3f", s.base_cost) +
          " | ";
    for (std::size_t k = 0; k < 4; ++k) md += std::to_string(s.activations[k]) + " | ";
    md += (decided.empty() ? "none" : decided) + " |\n";
  }
  const int n = static_cast<int>(c.scenarios.size());
  md += "\n| subsystem | acts in | decides |\n| --- | --- | --- |\n";
  for (std::size_t k = 0; k < 4; ++k)
    md += std::string("| ") + kCheckedSubsystems[k] + " | " + std::to_string(c.acting[k]) + " of " +
          std::to_string(n) + " | " + std::to_string(c.deciding[k]) + " of " + std::to_string(n) +
          " |\n";
  md += "\n";
  if (training)
    for (std::size_t k = 0; k < 4; ++k) {
      if (c.acting[k] == 0)
        md += std::string("warning: ") + kCheckedSubsystems[k] +
              " never acts in the training scenarios with the base set: its parameters cannot "
              "reach the cost, and a tune leaves them where the optimiser happens to stop\n";
      else if (c.deciding[k] == 0)
        md += std::string("note: ") + kCheckedSubsystems[k] +
              " acts but decides no training scenario (switching it off changes no outcome and "
              "no cost by 5 % or more): its parameters barely reach the cost\n";
    }
  return md;
}

}  // namespace scw::tuning
