#include "tuning/sim/scenario_set.h"

#include <filesystem>
#include <map>

#include "params/io/load.h"
#include "params/io/write.h"
#include "params/io/yaml_doc.h"
#include "tuning/sim/robust_set_yaml.h"
#include "tuning/sim/scenario.h"

namespace scw::tuning {
namespace {

using Overrides = std::vector<std::string>;

/// A critical situation, driven for one lap (on `track`, "" = the default). Survival is judged:
/// no spin (|β| 20°), no lock or spin of a wheel, on the track; running wide by more than the
/// studies' 3 m is allowed (the lateral-error abort at 10 m).
Overrides Critical(const Overrides& situation, const std::string& track = "") {
  Overrides o = {"kind=critical"};
  if (!track.empty()) o.push_back("track=" + track);
  o.insert(o.end(), {"laps=1", "abort.max_lateral_error=10"});
  o.insert(o.end(), situation.begin(), situation.end());
  return o;
}

/// A timed event of `block` on lap 1, `s` metres from the apex of `corner`; `magnitude` is
/// "key=[value]" of the block (value, factor).
Overrides Timed(const std::string& block, const std::string& corner, const std::string& s,
                const std::string& duration, const std::string& magnitude) {
  const std::string e = "events." + block + ".";
  return {e + "corner=[" + corner + "]", e + "s=[" + s + "]", e + "lap=[1]",
          e + "duration=[" + duration + "]", e + magnitude};
}

Overrides LateBraking(const std::string& corner, const std::string& distance) {
  return {"events.late_braking.corner=[" + corner + "]", "events.late_braking.s=[0]",
          "events.late_braking.distance=[" + distance + "]"};
}

/// A patch of other grip over the whole width from `start` to `end` [m].
Overrides WetPatch(const std::string& start, const std::string& end, const std::string& factor) {
  return {"friction_patches.start=[" + start + "]", "friction_patches.end=[" + end + "]",
          "friction_patches.n_min=[-100]", "friction_patches.n_max=[100]",
          "friction_patches.factor=[" + factor + "]"};
}

}  // namespace

ScenarioSet ScenarioSet::Robust() {
  return FromYamlText(generated::kRobustSetYaml, "built-in robust set");
}

ScenarioSet ScenarioSet::FromNameOrFile(const std::string& name_or_path) {
  if (name_or_path.empty() || name_or_path == "default") return Default();
  if (name_or_path == "robust") return Robust();
  return FromFile(name_or_path);
}

ScenarioSet ScenarioSet::Default() {
  ScenarioSet s;
  s.name = "default";
  // A critical run saved metres off its line is not saved well: beyond the 3 m at which the
  // paper's simulation studies stop a run, each metre costs 10 s (issue 47's stability objective:
  // aborts, sideslip and lateral error on the critical scenarios).
  s.cost.lateral_error_allowed_m = 3.0;
  s.cost.lateral_error_weight = 10.0;
  // Training (Yas Marina North, docs/scenarios.md): two clean laps near the limit, where every
  // intervention costs lap time, and the critical situations chosen by one rule: each corner-placed
  // event of the library (full throttle for 1 s at the apex or 20 m after it, braking 20 m late,
  // rear grip × 0.65 for 1.5 s at the apex) at every corner of the track where it makes the car
  // fail without stability control (measured), except the corner the held-out set uses for that
  // event; plus the wet braking zone of corner 1. Some of them the shipped set survives (one or
  // more of ESC, countersteer, ABS and TC decide them), some it does not: the tuner can gain there.
  // One lap each, the event on it, except the 2-lap clean run, to keep the default tune within
  // minutes.
  auto power_on = [](const std::string& corner, const std::string& offset) {
    return Critical(Timed("throttle", corner, offset, "1.0", "value=[1.0]"));
  };
  auto rear_grip_loss = [](const std::string& corner) {
    return Critical(Timed("rear_grip", corner, "0", "1.5", "factor=[0.65]"));
  };
  s.training = {
      {"clean_gg1.2", 1.0, "", {"kind=clean", "gg_scale=1.2", "laps=2"}},
      {"clean_gg1.1", 1.0, "", {"kind=clean", "gg_scale=1.1", "laps=1"}},
      {"power_on_c1_apex", 1.0, "", power_on("1", "0")},
      {"power_on_c1", 1.0, "", power_on("1", "20")},
      {"power_on_c3_apex", 1.0, "", power_on("3", "0")},
      {"power_on_c3", 1.0, "", power_on("3", "20")},
      {"power_on_c5_apex", 1.0, "", power_on("5", "0")},
      {"power_on_c7", 1.0, "", power_on("7", "20")},
      {"power_on_c8_apex", 1.0, "", power_on("8", "0")},
      {"power_on_c8", 1.0, "", power_on("8", "20")},
      {"late_braking_c1", 1.0, "", Critical(LateBraking("1", "20"))},
      {"late_braking_c5", 1.0, "", Critical(LateBraking("5", "20"))},
      {"late_braking_c7", 1.0, "", Critical(LateBraking("7", "20"))},
      {"late_braking_c8", 1.0, "", Critical(LateBraking("8", "20"))},
      {"wet_braking_c1", 1.0, "", Critical(WetPatch("180", "260", "0.8"))},
      {"rear_grip_loss_c3", 1.0, "", rear_grip_loss("3")},
      {"rear_grip_loss_c5", 1.0, "", rear_grip_loss("5")},
      {"rear_grip_loss_c9", 1.0, "", rear_grip_loss("9")},
  };
  // Held out: other corners, places, magnitudes, and another track (Monza).
  s.held_out = {
      {"clean_gg1.15", 1.0, "", {"kind=clean", "gg_scale=1.15", "laps=1"}},
      {"monza_clean_gg1.1", 1.0, "", {"kind=clean", "track=monza", "gg_scale=1.1", "laps=1"}},
      {"power_on_c2", 1.0, "", Critical(Timed("throttle", "2", "10", "0.8", "value=[0.9]"))},
      {"monza_power_on_c10", 1.0, "",
       Critical(Timed("throttle", "10", "20", "1.0", "value=[1.0]"), "monza")},
      {"late_braking_c9", 1.0, "", Critical(LateBraking("9", "20"))},
      {"wet_braking_c7", 1.0, "", Critical(WetPatch("2470", "2540", "0.8"))},
      {"rear_grip_loss_c2", 1.0, "", Critical(Timed("rear_grip", "2", "0", "1.5", "factor=[0.7]"))},
      {"low_mu_traction_0.65", 1.0, "",
       Critical({"grip.rear_mu_x=0.65", "plan_with_nominal_grip=true", "gg_scale=1.0"})},
  };
  return s;
}

void ScenarioSetFile::CrossCheck(const ScenarioSetFile& f, Problems& pr) {
  // Names identify scenarios in every report and log: one name, one scenario. A block's names
  // are those of its expansion; one without a name or too large to expand names nothing (its own
  // rules report it). A block's clashes are one problem, naming the first.
  std::map<std::string, std::string> seen;  // name → what it names, for the message
  auto check = [&](const std::vector<SetEntry>& list, const std::string& where) {
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string at = params::ListItemPath(where, i);
      if (const auto* e = std::get_if<ScenarioEntry>(&list[i])) {
        if (e->name.empty()) continue;
        const auto [it, fresh] = seen.emplace(e->name, at);
        if (!fresh) pr.Add(at + ".name", "'" + e->name + "' is already the name of " + it->second);
        continue;
      }
      const auto& block = std::get<MonteCarloBlock>(list[i]);
      const std::string path = at + ".monte_carlo";
      const std::size_t n = block.Size();
      if (block.name.empty() || n > kMaxMonteCarloScenarios) continue;
      std::size_t clashes = 0;
      std::string first;
      for (std::size_t k = 0; k < n; ++k) {
        const std::string name = block.ScenarioName(k);
        const auto [it, fresh] =
            seen.emplace(name, "scenario " + std::to_string(k) + " of " + path);
        if (!fresh && clashes++ == 0)
          first = "'" + name + "' (its scenario " + std::to_string(k) +
                  ") is already the name of " + it->second;
      }
      if (clashes > 0)
        pr.Add(path + ".name",
               first + (clashes > 1 ? " (and " + std::to_string(clashes - 1) + " more)" : ""));
    }
  };
  check(f.training, "training");
  if (f.held_out) check(*f.held_out, "held_out");
}

ScenarioSet ScenarioSet::FromYamlText(const std::string& text, const std::string& file) {
  const auto f = params::LoadPlainText<ScenarioSetFile>(text, file);
  ScenarioSet s;
  s.name = f.name;
  if (f.cost) s.cost = *f.cost;
  s.base_dir = std::filesystem::path(file).parent_path().string();
  auto expand = [](const std::vector<SetEntry>& list, std::vector<ScenarioEntry>* out) {
    for (const auto& entry : list) {
      if (const auto* e = std::get_if<ScenarioEntry>(&entry)) {
        out->push_back(*e);
      } else {
        auto drawn = std::get<MonteCarloBlock>(entry).Expand();
        out->insert(out->end(), std::make_move_iterator(drawn.begin()),
                    std::make_move_iterator(drawn.end()));
      }
    }
  };
  expand(f.training, &s.training);
  if (f.held_out) expand(*f.held_out, &s.held_out);
  return s;
}

ScenarioSet ScenarioSet::FromFile(const std::string& path) {
  return FromYamlText(params::ReadTextFile(path), path);
}

ScenarioSetFile ScenarioSet::ToFile() const {
  ScenarioSetFile f;
  f.name = name;
  f.cost = cost;
  f.training.assign(training.begin(), training.end());
  if (!held_out.empty()) f.held_out.emplace(held_out.begin(), held_out.end());
  return f;
}

std::string ScenarioSet::ToYaml() const {
  return params::ToPlainYaml(ToFile(), "", params::TextStyle::kPlainWhereSafe);
}

params::ScenarioParams LoadEntry(const ScenarioEntry& e, const std::string& base_dir) {
  params::ScenarioParams spec;
  if (!e.file.empty()) {
    const std::string path = base_dir.empty() || std::filesystem::path(e.file).is_absolute()
                                 ? e.file
                                 : (std::filesystem::path(base_dir) / e.file).string();
    spec = LoadScenario(path, e.overrides);
  } else {
    spec = DefaultScenario(e.overrides);
  }
  spec.name = e.name;
  return spec;
}

}  // namespace scw::tuning
