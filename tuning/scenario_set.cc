#include "tuning/scenario_set.h"

#include <cctype>
#include <filesystem>

#include "params/io/load.h"
#include "params/io/override.h"
#include "params/io/write.h"
#include "params/io/yaml_doc.h"
#include "tuning/scenario.h"

namespace scw::tuning {
namespace {

using params::YamlNode;

std::vector<ScenarioEntry> ReadEntries(const YamlNode& list, const std::string& where,
                                       Problems* pr) {
  std::vector<ScenarioEntry> out;
  if (list.kind != YamlNode::Kind::kSequence || list.items.empty()) {
    pr->Add(where, "must be a non-empty list of {name, weight, file, set}");
    return out;
  }
  for (std::size_t i = 0; i < list.items.size(); ++i) {
    const YamlNode& item = list.items[i];
    const std::string at = where + "[" + std::to_string(i) + "]";
    const std::string line = " (line " + std::to_string(item.line) + ")";
    if (item.kind != YamlNode::Kind::kMap) {
      pr->Add(at, "must be a map {name, weight, file, set}" + line);
      continue;
    }
    ScenarioEntry e;
    for (const auto& [k, v] : item.entries) {
      const std::string path = at + "." + k;
      if (k == "set") {
        if (v.kind != YamlNode::Kind::kSequence) {
          pr->Add(path, "must be a list of key=value overrides" + line);
          continue;
        }
        for (const auto& o : v.items) {
          if (o.kind != YamlNode::Kind::kScalar || o.text.find('=') == std::string::npos)
            pr->Add(path, "each override must look like key=value" + line);
          else
            e.overrides.push_back(o.text);
        }
        continue;
      }
      if (v.kind != YamlNode::Kind::kScalar) {
        pr->Add(path, "must be a single value" + line);
        continue;
      }
      if (k == "name") {
        e.name = v.text;
      } else if (k == "file") {
        e.file = v.text;
      } else if (k == "weight") {
        if (!params::ParseDouble(v.text, &e.weight) || !(e.weight >= 0) || !std::isfinite(e.weight))
          pr->Add(path, "must be a finite number >= 0, got '" + v.text + "'" + line);
      } else {
        pr->Add(path, "unknown key (expected name, weight, file, set)" + line);
      }
    }
    if (e.name.empty()) pr->Add(at + ".name", "required key is missing" + line);
    out.push_back(e);
  }
  return out;
}

// A scalar for a flow map written by ToYaml: plain when it reads back as the same text (letters,
// digits, _ . - + = /, not starting with an indicator, not a null word), else double-quoted.
std::string Scalar(const std::string& s) {
  bool plain = !s.empty() && (std::isalnum(static_cast<unsigned char>(s[0])) || s[0] == '_');
  for (unsigned char c : s)
    plain = plain && (std::isalnum(c) || c == '_' || c == '.' || c == '-' || c == '+' || c == '=' ||
                      c == '/');
  plain = plain && s != "null" && s != "Null" && s != "NULL";  // YAML reads those as null
  return plain ? s : params::QuoteString(s);
}

std::string EntriesYaml(const std::vector<ScenarioEntry>& entries) {
  std::string out;
  for (const auto& e : entries) {
    out += "  - {name: " + Scalar(e.name) + ", weight: " + params::FormatDouble(e.weight);
    if (!e.file.empty()) out += ", file: " + params::QuoteString(e.file);
    out += ", set: [";
    for (std::size_t i = 0; i < e.overrides.size(); ++i) {
      const std::string& o = e.overrides[i];
      out += (i ? ", " : "") + Scalar(o);
    }
    out += "]}\n";
  }
  return out;
}

}  // namespace

ScenarioSet ScenarioSet::Default() {
  ScenarioSet s;
  s.name = "default";
  // Training: the four situations the issue names, 2 laps each (flying lap + one) to keep a
  // tuning run within minutes; the held-out set drives 3 laps at neighbouring conditions.
  s.training = {
      {"nominal_gg1.2", 1.0, "", {"gg_scale=1.2", "laps=2"}},
      {"rear_grip-20_gg1.3",
       1.0,
       "",
       {"grip.rear_mu_y=0.8", "gg_scale=1.3", "laps=2", "abort.lock_slip_pct=100"}},
      {"low_mu_braking",
       1.0,
       "",
       {"grip.mu=0.7", "plan_with_nominal_grip=true", "gg_scale=1.1", "laps=2"}},
      {"low_mu_traction",
       1.0,
       "",
       {"grip.rear_mu_x=0.7", "plan_with_nominal_grip=true", "gg_scale=1.1", "laps=2"}},
  };
  s.held_out = {
      {"nominal_gg1.1", 1.0, "", {"gg_scale=1.1"}},
      {"rear_grip-15_gg1.25",
       1.0,
       "",
       {"grip.rear_mu_y=0.85", "gg_scale=1.25", "abort.lock_slip_pct=100"}},
      {"low_mu_braking_0.75",
       1.0,
       "",
       {"grip.mu=0.75", "plan_with_nominal_grip=true", "gg_scale=1.1"}},
      {"low_mu_traction_0.65",
       1.0,
       "",
       {"grip.rear_mu_x=0.65", "plan_with_nominal_grip=true", "gg_scale=1.0"}},
      {"mu_split_left",
       1.0,
       "",
       {"grip.wheel_mu_x=[0.8, 1.0, 0.8, 1.0]", "grip.wheel_mu_y=[0.8, 1.0, 0.8, 1.0]",
        "gg_scale=1.1"}},
  };
  return s;
}

ScenarioSet ScenarioSet::FromYamlText(const std::string& text, const std::string& file) {
  const YamlNode root = params::ParseYaml(text, file);
  if (root.kind != YamlNode::Kind::kMap) throw ConfigError(file, "", "top level must be a map");
  ScenarioSet s;
  s.base_dir = std::filesystem::path(file).parent_path().string();
  Problems pr;
  bool has_training = false;
  for (const auto& [k, v] : root.entries) {
    if (k == "name" && v.kind == YamlNode::Kind::kScalar) {
      s.name = v.text;
    } else if (k == "training") {
      s.training = ReadEntries(v, "training", &pr);
      has_training = true;
    } else if (k == "held_out") {
      s.held_out = ReadEntries(v, "held_out", &pr);
    } else if (k == "cost") {
      // Re-use the strict plain loader on the sub-map.
      YamlNode wrapper;
      wrapper.kind = YamlNode::Kind::kMap;
      try {
        std::string sub;
        for (const auto& [ck, cv] : v.entries) sub += ck + ": " + params::Render(cv) + "\n";
        s.cost = params::LoadPlainText<params::CostWeights>(sub.empty() ? "{}" : sub, file);
      } catch (const ConfigError& e) {
        for (const auto& p : e.problems()) pr.Add("cost." + p.path, p.message);
      }
    } else {
      pr.Add(k, "unknown key (expected name, cost, training, held_out)");
    }
  }
  if (!has_training) pr.Add("training", "required key is missing");
  if (!pr.empty()) throw ConfigError(file, pr.items());
  return s;
}

ScenarioSet ScenarioSet::FromFile(const std::string& path) {
  return FromYamlText(params::ReadTextFile(path), path);
}

std::string ScenarioSet::ToYaml() const {
  std::string out = "name: " + Scalar(name) + "\n";
  out += "cost:\n";
  const std::string cost_yaml = params::ToPlainYaml(cost);
  std::size_t start = 0;
  while (start < cost_yaml.size()) {
    const auto nl = cost_yaml.find('\n', start);
    out += "  " + cost_yaml.substr(start, nl - start) + "\n";
    start = nl + 1;
  }
  out += "training:\n" + EntriesYaml(training);
  if (!held_out.empty()) out += "held_out:\n" + EntriesYaml(held_out);
  return out;
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
