#include "tuning/replay/replay.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <utility>

namespace scw::tuning::replay {

using controller::StabilityController;
using controller::StabilityInput;
using controller::StabilityOutput;

namespace {

using Getter = double (*)(const StabilityOutput&) noexcept;

struct OutputColumnDef {
  std::string_view name;
  std::string_view unit;
  std::string_view doc;
  Getter get;  // nullptr: the time column (not part of StabilityOutput)
};

double Flag(bool b) noexcept { return b ? 1.0 : 0.0; }

template <std::size_t W>
double PressureOut(const StabilityOutput& o) noexcept {
  return o.brake_bar[W];
}
template <std::size_t W>
double AbsState(const StabilityOutput& o) noexcept {
  return static_cast<double>(controller::ToInt(o.abs_state[W]));
}
template <std::size_t W>
double TcState(const StabilityOutput& o) noexcept {
  return static_cast<double>(controller::ToInt(o.tc_state[W]));
}
template <std::size_t W>
double SlipOut(const StabilityOutput& o) noexcept {
  return o.slip_pct[W];
}
template <std::size_t W>
double AlphaOut(const StabilityOutput& o) noexcept {
  return o.slip_angle[W];
}

// The one list of output columns: name, unit, meaning and value.
// clang-format off
constexpr std::array<OutputColumnDef, 27> kOutputDefs = {{
    {"t_s", "s", "time stamp of the input row", nullptr},
    {"steer_out_rad", "rad", "steering command after countersteer (clamped to the steering limits)", [](const StabilityOutput& o) noexcept { return o.steering; }},
    {"p_out_fl_bar", "bar", "brake pressure command after ESC and ABS/TC", &PressureOut<kFL>},
    {"p_out_fr_bar", "bar", "brake pressure command", &PressureOut<kFR>},
    {"p_out_rl_bar", "bar", "brake pressure command", &PressureOut<kRL>},
    {"p_out_rr_bar", "bar", "brake pressure command", &PressureOut<kRR>},
    {"throttle_out", "0..1", "throttle command (request x TC throttle cut)", [](const StabilityOutput& o) noexcept { return o.throttle; }},
    {"esc_active", "0/1", "ESC intervening", [](const StabilityOutput& o) noexcept { return Flag(o.esc_active); }},
    {"cs_active", "0/1", "countersteer intervening", [](const StabilityOutput& o) noexcept { return Flag(o.cs_active); }},
    {"slip_control_active", "0/1", "any ABS or (relevant) TC wheel latched (the node's topic)", [](const StabilityOutput& o) noexcept { return Flag(o.slip_control_active); }},
    {"abs_state_fl", "0..3", "ABS phase: 0 inactive, 1 reduce, 2 hold, 3 increase", &AbsState<kFL>},
    {"abs_state_fr", "0..3", "ABS phase", &AbsState<kFR>},
    {"abs_state_rl", "0..3", "ABS phase", &AbsState<kRL>},
    {"abs_state_rr", "0..3", "ABS phase", &AbsState<kRR>},
    {"tc_state_fl", "0..3", "TC phase: 0 inactive, 1 reduce, 2 hold, 3 increase", &TcState<kFL>},
    {"tc_state_fr", "0..3", "TC phase", &TcState<kFR>},
    {"tc_state_rl", "0..3", "TC phase", &TcState<kRL>},
    {"tc_state_rr", "0..3", "TC phase", &TcState<kRR>},
    {"yaw_moment_Nm", "N*m", "ESC yaw-moment demand, > 0 turns left (0 when inactive)", [](const StabilityOutput& o) noexcept { return o.yaw_moment; }},
    {"slip_est_fl_pct", "%", "longitudinal slip as the controller estimates it (< 0 braking), with the low-speed fade", &SlipOut<kFL>},
    {"slip_est_fr_pct", "%", "longitudinal slip", &SlipOut<kFR>},
    {"slip_est_rl_pct", "%", "longitudinal slip", &SlipOut<kRL>},
    {"slip_est_rr_pct", "%", "longitudinal slip", &SlipOut<kRR>},
    {"alpha_est_fl_rad", "rad", "tyre slip angle as the controller estimates it (> 0 gives a leftward force), with the low-speed fade", &AlphaOut<kFL>},
    {"alpha_est_fr_rad", "rad", "tyre slip angle", &AlphaOut<kFR>},
    {"alpha_est_rl_rad", "rad", "tyre slip angle", &AlphaOut<kRL>},
    {"alpha_est_rr_rad", "rad", "tyre slip angle", &AlphaOut<kRR>},
}};
// clang-format on

constexpr std::array<OutputColumn, kOutputDefs.size()> OutputColumns() {
  std::array<OutputColumn, kOutputDefs.size()> cols{};
  for (std::size_t i = 0; i < kOutputDefs.size(); ++i)
    cols[i] = {kOutputDefs[i].name, kOutputDefs[i].unit, kOutputDefs[i].doc};
  return cols;
}

bool SameValue(double a, double b) noexcept {
  return a == b ? std::signbit(a) == std::signbit(b) : (std::isnan(a) && std::isnan(b));
}

void Track(MaxDifference* m, double a, double b, double t) {
  const double d = std::abs(a - b);
  if (d > m->value) {
    m->value = d;
    m->t = t;
  }
}

std::string Num(double x, int precision = 6) {
  if (std::isnan(x)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*g", precision, x);
  return buf;
}

std::string Fixed(double x, int decimals) {
  if (std::isnan(x)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, x);
  return buf;
}

std::string Pad(std::string s, std::size_t width, bool right = true) {
  if (s.size() >= width) return s;
  const std::string fill(width - s.size(), ' ');
  return right ? fill + s : s + fill;
}

std::string AtTime(const MaxDifference& m, const char* unit) {
  std::string s = Num(m.value) + (*unit ? " " : "") + unit;
  if (m.value > 0.0) s += " (at t = " + Fixed(m.t, 3) + " s)";
  return s;
}

}  // namespace

const std::array<OutputColumn, 27> kOutputColumns = OutputColumns();

double OutputValue(const StabilityOutput& out, std::size_t column) noexcept {
  const Getter g = kOutputDefs[column].get;
  return g != nullptr ? g(out) : kNever;
}

bool IsActive(Subsystem s, const StabilityOutput& out) noexcept {
  auto any = [](const PerWheel<controller::SlipPhase>& ph) {
    for (auto p : ph)
      if (controller::IsActive(p)) return true;
    return false;
  };
  switch (s) {
    case Subsystem::kEsc:
      return out.esc_active;
    case Subsystem::kCountersteer:
      return out.cs_active;
    case Subsystem::kAbs:
      return any(out.abs_state);
    case Subsystem::kTc:
      return any(out.tc_state);
  }
  return false;
}

// ---------------------------------------------------------------------------------------------

ReplayOutputWriter::ReplayOutputWriter(const std::string& path) : file_(path) {
  for (std::size_t i = 0; i < kOutputColumns.size(); ++i) {
    if (i) row_ += ',';
    row_ += kOutputColumns[i].name;
  }
  row_ += '\n';
  file_.Append(row_);
}

void ReplayOutputWriter::Write(double t, const StabilityOutput& out) {
  row_.clear();
  detail::AppendNumber(&row_, t);
  for (std::size_t i = 1; i < kOutputDefs.size(); ++i) {
    row_ += ',';
    detail::AppendNumber(&row_, kOutputDefs[i].get(out));
  }
  row_ += '\n';
  file_.Append(row_);
  ++rows_;
}

void ReplayOutputWriter::Commit() { file_.Commit(); }

// ---------------------------------------------------------------------------------------------

ReplaySummaryBuilder::ReplaySummaryBuilder(std::string log, double sample_time) : tS_(sample_time) {
  s_.log = std::move(log);
}

void ReplaySummaryBuilder::Add(double t, const StabilityOutput& out) {
  const double dt = s_.rows > 0 ? t - s_.t_last : 0.0;
  if (s_.rows == 0) s_.t_first = t;
  ++s_.rows;
  s_.t_last = t;
  if (out.valid) {
    ++s_.valid_rows;
    if (!out.slip_valid) ++s_.no_slip_rows;
  } else {
    ++s_.invalid_rows;
  }
  for (std::size_t k = 0; k < kNumSubsystems; ++k) {
    SubsystemActivity& a = s_.activity[k];
    if (prev_active_[k]) a.active_time += dt;  // the previous row's output held until now
    const bool active = IsActive(static_cast<Subsystem>(k), out);
    if (active) {
      if (!prev_active_[k]) ++a.interventions;
      if (a.active_rows == 0) a.first_active_t = t;
      ++a.active_rows;
    }
    prev_active_[k] = active;
  }
}

ReplaySummary ReplaySummaryBuilder::Finish() const {
  ReplaySummary s = s_;
  for (std::size_t k = 0; k < kNumSubsystems; ++k)
    if (prev_active_[k]) s.activity[k].active_time += tS_;
  return s;
}

// ---------------------------------------------------------------------------------------------

namespace {
void ApplyInputOptions(const ReplayInputOptions& o, StabilityInput* in) {
  if (o.estimate_loads) in->fz_external = StabilityInput{}.fz_external;
}
}  // namespace

ReplaySummary ReplayLog(const std::string& log_path, const StabilityController& controller,
                        const std::string& output_path, const ReplayInputOptions& input) {
  ControllerLogReader reader(log_path);
  std::optional<ReplayOutputWriter> writer;
  if (!output_path.empty()) writer.emplace(output_path);
  ReplaySummaryBuilder summary(log_path, controller.sample_time());
  StabilityController::State state;
  StabilityInput in;
  while (reader.Next(&in)) {
    ApplyInputOptions(input, &in);
    const StabilityOutput out = controller.Step(in, &state);
    summary.Add(in.t, out);
    if (writer) writer->Write(in.t, out);
  }
  if (writer) writer->Commit();
  return summary.Finish();
}

ComparisonSummary CompareOnLog(const std::string& log_path, const StabilityController& a,
                               const StabilityController& b, const std::string& output_path,
                               const ReplayInputOptions& input) {
  ControllerLogReader reader(log_path);
  std::optional<ReplayOutputWriter> writer;
  if (!output_path.empty()) writer.emplace(output_path);
  ReplaySummaryBuilder sum_a(log_path, a.sample_time());
  ReplaySummaryBuilder sum_b(log_path, b.sample_time());
  StabilityController::State state_a;
  StabilityController::State state_b;
  ComparisonSummary c;
  StabilityInput in;
  while (reader.Next(&in)) {
    ApplyInputOptions(input, &in);
    const StabilityOutput oa = a.Step(in, &state_a);
    const StabilityOutput ob = b.Step(in, &state_b);
    sum_a.Add(in.t, oa);
    sum_b.Add(in.t, ob);
    if (writer) writer->Write(in.t, oa);

    Track(&c.steering, oa.steering, ob.steering, in.t);
    for (std::size_t w = 0; w < 4; ++w)
      Track(&c.pressure_bar[w], oa.brake_bar[w], ob.brake_bar[w], in.t);
    Track(&c.throttle, oa.throttle, ob.throttle, in.t);
    Track(&c.yaw_moment, oa.yaw_moment, ob.yaw_moment, in.t);

    for (std::size_t i = 1; i < kOutputDefs.size(); ++i) {
      if (SameValue(kOutputDefs[i].get(oa), kOutputDefs[i].get(ob))) continue;
      ++c.differing_rows;
      if (!c.diverged) {
        c.diverged = true;
        c.first_divergence_t = in.t;
        c.first_divergence_line = reader.line();
        c.first_divergence_column = std::string(kOutputDefs[i].name);
      }
      break;
    }
  }
  if (writer) writer->Commit();
  c.a = sum_a.Finish();
  c.b = sum_b.Finish();
  return c;
}

// ---------------------------------------------------------------------------------------------

std::string ColumnsMarkdown() {
  auto escape = [](std::string_view text) {
    std::string e;
    for (char ch : text) {
      if (ch == '|') e += '\\';
      e += ch;
    }
    return e;
  };
  std::string r =
      "Input columns (controller log):\n\n| Column | Unit | Required | Old name (read) | Meaning "
      "|\n| --- | --- | --- | --- | --- |\n";
  for (const auto& c : kInputColumns)
    r += "| `" + std::string(c.name) + "` | " + std::string(c.unit) + " | " +
         (c.integer    ? "yes (integer)"
          : c.required ? "yes"
                       : "no") +
         " | " + (c.alias.empty() ? std::string() : "`" + std::string(c.alias) + "`") + " | " +
         escape(c.doc) + " |\n";
  r += "\nOutput columns (`-o`):\n\n| Column | Unit | Meaning |\n| --- | --- | --- |\n";
  for (const auto& c : kOutputColumns)
    r +=
        "| `" + std::string(c.name) + "` | " + std::string(c.unit) + " | " + escape(c.doc) + " |\n";
  return r;
}

std::string FormatSummary(const ReplaySummary& s) {
  std::string r;
  r += "log:        " + s.log + "\n";
  r += "rows:       " + std::to_string(s.rows) + " (t = " + Fixed(s.t_first, 3) + " .. " +
       Fixed(s.t_last, 3) + " s, duration " + Fixed(s.duration(), 3) + " s)\n";
  r += "valid rows: " + std::to_string(s.valid_rows) +
       "; invalid (pass-through) rows: " + std::to_string(s.invalid_rows) +
       "; valid rows without wheel speeds: " + std::to_string(s.no_slip_rows) + "\n";
  r += "\n" + Pad("subsystem", 14, false) + Pad("interventions", 15) + Pad("active [s]", 12) +
       Pad("active rows", 13) + Pad("first at t [s]", 16) + "\n";
  for (std::size_t k = 0; k < kNumSubsystems; ++k) {
    const SubsystemActivity& a = s.activity[k];
    r += Pad(std::string(kSubsystemNames[k]), 14, false) +
         Pad(std::to_string(a.interventions), 15) + Pad(Fixed(a.active_time, 3), 12) +
         Pad(std::to_string(a.active_rows), 13) + Pad(Fixed(a.first_active_t, 3), 16) + "\n";
  }
  return r;
}

std::string FormatComparison(const ComparisonSummary& c, std::string_view name_a,
                             std::string_view name_b) {
  std::string r;
  r += "log:  " + c.a.log + "\n";
  r += "rows: " + std::to_string(c.a.rows) + " (duration " + Fixed(c.a.duration(), 3) +
       " s); invalid (pass-through) rows: " + std::to_string(c.a.invalid_rows) + "\n";
  r += "A:    " + std::string(name_a) + "\n";
  r += "B:    " + std::string(name_b) + "\n\n";
  r += Pad("subsystem", 14, false) + Pad("interventions A", 17) + Pad("B", 6) +
       Pad("active [s] A", 14) + Pad("B", 10) + "\n";
  for (std::size_t k = 0; k < kNumSubsystems; ++k) {
    const SubsystemActivity& a = c.a.activity[k];
    const SubsystemActivity& b = c.b.activity[k];
    r += Pad(std::string(kSubsystemNames[k]), 14, false) +
         Pad(std::to_string(a.interventions), 17) + Pad(std::to_string(b.interventions), 6) +
         Pad(Fixed(a.active_time, 3), 14) + Pad(Fixed(b.active_time, 3), 10) + "\n";
  }
  r += "\nmax |A - B| of the outputs:\n";
  r += "  steering:     " + AtTime(c.steering, "rad") + "\n";
  for (std::size_t w = 0; w < 4; ++w)
    r += std::string("  pressure ") + kWheelNames[w] + ":  " + AtTime(c.pressure_bar[w], "bar") +
         "\n";
  r += "  throttle:     " + AtTime(c.throttle, "") + "\n";
  r += "  yaw moment:   " + AtTime(c.yaw_moment, "N*m") + "\n\n";
  if (c.diverged)
    r += "outputs first diverge at t = " + Fixed(c.first_divergence_t, 3) + " s (log line " +
         std::to_string(c.first_divergence_line) + ", column " + c.first_divergence_column + "); " +
         std::to_string(c.differing_rows) + " of " + std::to_string(c.a.rows) + " rows differ\n";
  else
    r += "outputs identical in every row\n";
  return r;
}

}  // namespace scw::tuning::replay
