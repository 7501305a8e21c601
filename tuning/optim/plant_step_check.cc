#include "tuning/optim/plant_step_check.h"

#include <cmath>

#include "params/io/write.h"
#include "tuning/sim/run_summary.h"

namespace scw::tuning {
namespace {

/// Max |β| in degrees, as every rendering of RunMetrics shows it.
double MaxBetaDeg(const RunMetrics& m) {
  return params::RenderedValue(m.max_abs_sideslip,
                               params::OutputMeta{.key = "", .rad_to_deg = true});
}

/// "2 ms", "0.5 ms".
std::string Ms(double step_s) {
  std::string s = FormatFixed(step_s * 1e3, 3);
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s + " ms";
}

/// "ESC", "CS", "ABS", "TC" where exactly one of the two runs has activations.
std::vector<std::string> SubsystemsActingInOne(const RunMetrics& a, const RunMetrics& b) {
  std::vector<std::string> out;
  const auto one = [&](const char* name, int x, int y) {
    if ((x > 0) != (y > 0)) out.emplace_back(name);
  };
  one("ESC", a.esc_count, b.esc_count);
  one("CS", a.cs_count, b.cs_count);
  one("ABS", a.abs_count, b.abs_count);
  one("TC", a.tc_count, b.tc_count);
  return out;
}

std::string Outcome(const RunMetrics& m) {
  std::string s = RunStatusName(m.status);
  if (m.aborted()) s += " (" + FormatFixed(100.0 * m.Progress(), 1) + " %)";
  return s;
}

std::string Activations(const RunMetrics& m) {
  return std::to_string(m.esc_count) + "/" + std::to_string(m.cs_count) + "/" +
         std::to_string(m.abs_count) + "/" + std::to_string(m.tc_count);
}

}  // namespace

int OutcomeClass(RunStatus status) {
  switch (status) {
    case RunStatus::kCompleted:
      return 0;
    case RunStatus::kSideslip:
    case RunStatus::kLateralError:
    case RunStatus::kOffTrack:
      return 1;
    case RunStatus::kWheelLock:
    case RunStatus::kWheelSpin:
      return 2;
    case RunStatus::kNonFinite:
    case RunStatus::kTimeout:
    case RunStatus::kInvalidParams:
      return 3;
  }
  return 3;
}

std::string PlantStepCheck::Verdict() const {
  if (!ran) return "not run";
  return passed ? "passed" : "failed";
}

int PlantStepCheck::Passing() const {
  int n = 0;
  for (const auto& s : scenarios) n += s.failures.empty();
  return n;
}

std::vector<ScenarioEntry> WithPlantStep(std::vector<ScenarioEntry> entries, double step) {
  for (auto& e : entries) e.overrides.push_back("plant_step=" + params::FormatDouble(step));
  return entries;
}

bool StepDiffers(const BatchEvaluator& fine, double step) {
  for (const auto& sc : fine.scenarios())
    if (sc.vehicle.simulation.time_step != step) return true;
  return false;
}

PlantStepCheck ComparePlantSteps(double step, const std::vector<std::string>& scenarios,
                                 const SetEvaluation& fine_base, const SetEvaluation& coarse_base,
                                 const PlantStepTolerances& tol) {
  PlantStepCheck c;
  c.step = step;
  c.ran = true;
  c.fine_total = fine_base.total;
  c.coarse_total = coarse_base.total;
  bool ok = fine_base.invalid.empty() && coarse_base.invalid.empty();
  for (std::size_t i = 0; i < scenarios.size(); ++i) {
    PlantStepScenarioCheck s;
    s.scenario = scenarios[i];
    if (i < fine_base.runs.size()) s.fine = fine_base.runs[i];
    if (i < coarse_base.runs.size()) s.coarse = coarse_base.runs[i];
    const RunMetrics& f = s.fine;
    const RunMetrics& g = s.coarse;
    if (OutcomeClass(f.status) != OutcomeClass(g.status)) {
      s.failures.push_back("outcome " + Outcome(f) + " vs " + Outcome(g));
    } else if (f.aborted()) {
      const double d = std::abs(g.Progress() - f.Progress());
      if (!(d <= tol.progress))
        s.failures.push_back("abort point moved by " + FormatFixed(100.0 * d, 1) +
                             " % of the distance (allowed " + FormatFixed(100.0 * tol.progress, 1) +
                             " %)");
    } else {
      const double d = std::abs(g.MeanLapTime() - f.MeanLapTime());
      if (!(d <= tol.lap_time_s))
        s.failures.push_back("lap time moved by " + FormatFixed(d, 3) + " s (allowed " +
                             FormatFixed(tol.lap_time_s, 3) + " s)");
    }
    const double dbeta = std::abs(MaxBetaDeg(g) - MaxBetaDeg(f));
    if (!(dbeta <= tol.max_beta_deg))
      s.failures.push_back("max |beta| moved by " + FormatFixed(dbeta, 2) + " deg (allowed " +
                           FormatFixed(tol.max_beta_deg, 2) + " deg)");
    for (const auto& name : SubsystemsActingInOne(f, g))
      s.failures.push_back(name + " acts at one step only (" + Activations(f) + " vs " +
                           Activations(g) + ")");
    ok = ok && s.failures.empty();
    c.scenarios.push_back(std::move(s));
  }
  const double rel =
      std::abs(c.coarse_total - c.fine_total) / std::max(std::abs(c.fine_total), 1e-9);
  if (!(rel <= tol.total_cost)) ok = false;
  c.passed = ok;
  return c;
}

std::string PlantStepCheckLine(const PlantStepCheck& c) {
  if (c.step <= 0.0) return "search plant step: each vehicle's own";
  if (!c.ran) return "search plant step " + Ms(c.step) + ": the vehicles' own step already";
  const double rel = (c.coarse_total - c.fine_total) / std::max(std::abs(c.fine_total), 1e-9);
  std::string s = "search plant step " + Ms(c.step) + ": check " + c.Verdict() + " (" +
                  std::to_string(c.Passing()) + " of " + std::to_string(c.scenarios.size()) +
                  " training scenarios alike, base cost " + FormatFixed(c.fine_total, 2) + " -> " +
                  FormatFixed(c.coarse_total, 2) + ", " + (rel >= 0 ? "+" : "") +
                  FormatFixed(100.0 * rel, 3) + " %)";
  if (!c.passed) s += "; searching at each vehicle's own step instead";
  return s;
}

std::string PlantStepCheckMarkdown(const PlantStepCheck& c) {
  std::string md = "## Search plant step\n\n" + PlantStepCheckLine(c) + ".\n";
  if (!c.ran) return md;
  md +=
      "\nThe optimiser evaluated the candidates at the search step only if the base set gives "
      "the same outcomes there as at each vehicle's own step on every training scenario "
      "(docs/plant-step.md); every table of this report runs at the vehicle's own step.\n\n"
      "| scenario | outcome (own / search) | mean lap [s] | max abs beta [deg] | "
      "ESC/CS/ABS/TC | check |\n"
      "| --- | --- | ---: | ---: | ---: | --- |\n";
  for (const auto& s : c.scenarios) {
    const auto lap = [](const RunMetrics& m) {
      const double t = m.MeanLapTime();
      return std::isnan(t) ? std::string("-") : FormatFixed(t, 3);
    };
    std::string verdict = "ok";
    if (!s.failures.empty()) {
      verdict.clear();
      for (const auto& f : s.failures) verdict += (verdict.empty() ? "" : "; ") + f;
    }
    md += "| " + s.scenario + " | " + Outcome(s.fine) + " / " + Outcome(s.coarse) + " | " +
          lap(s.fine) + " / " + lap(s.coarse) + " | " + FormatFixed(MaxBetaDeg(s.fine), 2) + " / " +
          FormatFixed(MaxBetaDeg(s.coarse), 2) + " | " + Activations(s.fine) + " / " +
          Activations(s.coarse) + " | " + verdict + " |\n";
  }
  return md + "\n";
}

}  // namespace scw::tuning
