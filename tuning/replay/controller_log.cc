#include "tuning/replay/controller_log.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>

#include "params/io/csv.h"
#include "params/io/suggest.h"
#include "params/io/text.h"

namespace scw::tuning::replay {

using controller::StabilityInput;

namespace {

constexpr LogColumn Real(std::string_view name, std::string_view alias, std::string_view unit,
                         bool required, double StabilityInput::*member, std::string_view doc) {
  return LogColumn{name, unit, required, member, nullptr, 0, nullptr, doc, alias};
}
constexpr LogColumn Wheel(std::string_view name, std::string_view alias, std::string_view unit,
                          bool required, PerWheel<double> StabilityInput::*member,
                          std::size_t wheel, std::string_view doc) {
  return LogColumn{name, unit, required, nullptr, member, wheel, nullptr, doc, alias};
}
constexpr LogColumn Integer(std::string_view name, int StabilityInput::*member,
                            std::string_view doc) {
  return LogColumn{name, "-", true, nullptr, nullptr, 0, member, doc, ""};
}

constexpr bool kRequired = true;
constexpr bool kOptional = false;

}  // namespace

// clang-format off
const std::array<LogColumn, 36> kInputColumns = {
    Real("t_s", "t", "s", kRequired, &StabilityInput::t, "controller time stamp (finite, never decreasing)"),
    Real("vx_mps", "vx", "m/s", kRequired, &StabilityInput::v_x, "longitudinal speed at the CoG, body frame"),
    Real("vy_mps", "vy", "m/s", kRequired, &StabilityInput::v_y, "lateral speed at the CoG, body frame, > 0 left"),
    Real("yaw_rate_radps", "yaw_rate", "rad/s", kRequired, &StabilityInput::yaw_rate, "yaw rate, > 0 left"),
    Real("ax_mps2", "ax", "m/s^2", kRequired, &StabilityInput::a_x, "longitudinal acceleration"),
    Real("ay_mps2", "ay", "m/s^2", kRequired, &StabilityInput::a_y, "lateral acceleration, > 0 left"),
    Real("steer_meas_rad", "steer_meas", "rad", kOptional, &StabilityInput::steering_measured, "steering report (tyre angle), > 0 left"),
    Real("steer_req_rad", "steer_req", "rad", kRequired, &StabilityInput::steering_request, "requested tyre angle, > 0 left"),
    Real("ay_req_mps2", "ay_req", "m/s^2", kOptional, &StabilityInput::ay_request, "ESC target lateral acceleration"),
    Real("yaw_rate_req_radps", "yaw_rate_req", "rad/s", kOptional, &StabilityInput::yaw_rate_request, "ESC target yaw rate"),
    Real("beta_req_rad", "beta_req", "rad", kOptional, &StabilityInput::beta_request, "ESC target sideslip angle"),
    Wheel("p_req_fl_bar", "p_req_fl", "bar", kRequired, &StabilityInput::brake_request_bar, kFL, "requested brake pressure"),
    Wheel("p_req_fr_bar", "p_req_fr", "bar", kRequired, &StabilityInput::brake_request_bar, kFR, "requested brake pressure"),
    Wheel("p_req_rl_bar", "p_req_rl", "bar", kRequired, &StabilityInput::brake_request_bar, kRL, "requested brake pressure"),
    Wheel("p_req_rr_bar", "p_req_rr", "bar", kRequired, &StabilityInput::brake_request_bar, kRR, "requested brake pressure"),
    Real("throttle_req", "", "0..1", kRequired, &StabilityInput::throttle_request, "requested throttle"),
    Integer("gear_req", &StabilityInput::gear_request, "requested gear (integer)"),
    Integer("gear", &StabilityInput::gear, "engaged gear (integer)"),
    Real("engine_speed_radps", "engine_speed", "rad/s", kRequired, &StabilityInput::engine_speed, "engine speed (virtual slips only)"),
    Wheel("omega_fl_radps", "omega_fl", "rad/s", kRequired, &StabilityInput::wheel_speed, kFL, "wheel speed"),
    Wheel("omega_fr_radps", "omega_fr", "rad/s", kRequired, &StabilityInput::wheel_speed, kFR, "wheel speed"),
    Wheel("omega_rl_radps", "omega_rl", "rad/s", kRequired, &StabilityInput::wheel_speed, kRL, "wheel speed"),
    Wheel("omega_rr_radps", "omega_rr", "rad/s", kRequired, &StabilityInput::wheel_speed, kRR, "wheel speed"),
    Wheel("p_meas_fl_bar", "p_meas_fl", "bar", kRequired, &StabilityInput::brake_measured_bar, kFL, "measured brake pressure"),
    Wheel("p_meas_fr_bar", "p_meas_fr", "bar", kRequired, &StabilityInput::brake_measured_bar, kFR, "measured brake pressure"),
    Wheel("p_meas_rl_bar", "p_meas_rl", "bar", kRequired, &StabilityInput::brake_measured_bar, kRL, "measured brake pressure"),
    Wheel("p_meas_rr_bar", "p_meas_rr", "bar", kRequired, &StabilityInput::brake_measured_bar, kRR, "measured brake pressure"),
    Real("long_fx_N", "long_fx", "N", kRequired, &StabilityInput::long_fx, "requested total longitudinal force, drive > 0 (ignored with release_compat)"),
    Wheel("fz_fl_N", "fz_fl", "N", kOptional, &StabilityInput::fz_external, kFL, "vertical load: all four given replace the controller's own estimate (scw simulate writes the loads its controller used)"),
    Wheel("fz_fr_N", "fz_fr", "N", kOptional, &StabilityInput::fz_external, kFR, "vertical load"),
    Wheel("fz_rl_N", "fz_rl", "N", kOptional, &StabilityInput::fz_external, kRL, "vertical load"),
    Wheel("fz_rr_N", "fz_rr", "N", kOptional, &StabilityInput::fz_external, kRR, "vertical load"),
    Wheel("brake_temp_fl_degC", "brake_temp_fl", "degC", kOptional, &StabilityInput::brake_temperature_degc, kFL, "brake temperature (pad friction map)"),
    Wheel("brake_temp_fr_degC", "brake_temp_fr", "degC", kOptional, &StabilityInput::brake_temperature_degc, kFR, "brake temperature"),
    Wheel("brake_temp_rl_degC", "brake_temp_rl", "degC", kOptional, &StabilityInput::brake_temperature_degc, kRL, "brake temperature"),
    Wheel("brake_temp_rr_degC", "brake_temp_rr", "degC", kOptional, &StabilityInput::brake_temperature_degc, kRR, "brake temperature"),
};
// clang-format on

namespace {

std::string LinePath(std::int64_t line, const std::string& column) {
  std::string p = "line " + std::to_string(line);
  if (!column.empty()) p += ", column " + column;
  return p;
}

using io::Trim;

bool IsNanText(std::string_view s) {
  if (!s.empty() && (s.front() == '-' || s.front() == '+')) s.remove_prefix(1);
  if (s.size() != 3) return false;
  auto lower = [](char c) { return static_cast<char>(c | 0x20); };
  return lower(s[0]) == 'n' && lower(s[1]) == 'a' && lower(s[2]) == 'n';
}

/// Parses a real cell; NaN for `nan`/empty. False if not a number.
bool ParseReal(std::string_view s, double* out) {
  if (s.empty() || IsNanText(s)) {
    *out = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  if (s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size()) return false;
  *out = v;
  return true;
}

bool ParseInteger(std::string_view s, int* out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  int v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size()) return false;
  *out = v;
  return true;
}

std::string Suggest(std::string_view unknown) {
  std::string best;
  std::size_t best_d = 3;  // suggest only close names
  for (const auto& c : kInputColumns) {
    const std::size_t d = params::EditDistance(unknown, c.name, best_d);
    if (d < best_d) best_d = d, best = std::string(c.name);
    // A misspelt old name: suggest the current one.
    if (c.alias.empty()) continue;
    const std::size_t da = params::EditDistance(unknown, c.alias, best_d);
    if (da < best_d) best_d = da, best = std::string(c.name);
  }
  return best;
}

/// Text of the log in a message: never raw control bytes (io::Printable), at most 40 bytes.
std::string Quote(std::string_view s) { return "'" + io::Printable(s) + "'"; }

/// A column name as the header spells it, fit for a message path (`line 1, column NAME`).
std::string ColumnName(std::string_view s) { return io::Printable(s, 60); }

/// "a, b, c and 5 more" of at most `shown` names.
std::string NameList(const std::vector<std::string>& names, std::size_t shown) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < shown; ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > shown) out += " and " + std::to_string(names.size() - shown) + " more";
  return out;
}

/// A byte of a header line no text CSV has: a NUL anywhere, else the first other control
/// character (tab and CR aside), as "a NUL byte" / "a control character (\x1B)"; "" if none.
std::string BinaryByte(std::string_view line) {
  if (line.find('\0') != std::string_view::npos) return "a NUL byte";
  for (const char c : line) {
    const auto b = static_cast<unsigned char>(c);
    if ((b < 0x20 && c != '\t' && c != '\r') || b == 0x7F)
      return "a control character (" + io::Printable(std::string_view(&c, 1)) + ")";
  }
  return "";
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// LogFormatError

LogFormatError::LogFormatError(const std::string& file, std::int64_t line, std::string column,
                               const std::string& message)
    : ConfigError(file, LinePath(line, column), message), line_(line), column_(std::move(column)) {}

LogFormatError::LogFormatError(const std::string& file, std::vector<Problem> header_problems,
                               std::string first_column)
    : ConfigError(file, std::move(header_problems)), line_(1), column_(std::move(first_column)) {}

// ---------------------------------------------------------------------------------------------
// Number formatting

namespace detail {

void AppendNumber(std::string* out, double x) {
  if (std::isnan(x)) {
    out->append("nan");
    return;
  }
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof(buf), x);
  out->append(buf, res.ptr);
}

void AppendInteger(std::string* out, long long x) {
  char buf[24];
  const auto res = std::to_chars(buf, buf + sizeof(buf), x);
  out->append(buf, res.ptr);
}

}  // namespace detail

// ---------------------------------------------------------------------------------------------
// ControllerLogWriter

struct ControllerLogWriter::Impl {
  explicit Impl(const std::string& path) : file(path) {}
  io::AtomicWriter file;
  std::string row;
  std::int64_t rows = 0;
  std::int64_t bytes = 0;
  double last_t = -std::numeric_limits<double>::infinity();
};

ControllerLogWriter::ControllerLogWriter(const std::string& path)
    : impl_(std::make_unique<Impl>(path)) {
  std::string& h = impl_->row;
  for (std::size_t i = 0; i < kInputColumns.size(); ++i) {
    if (i) h += ',';
    h += kInputColumns[i].name;
  }
  h += '\n';
  impl_->file.Append(h);
  impl_->bytes += static_cast<std::int64_t>(h.size());
}

ControllerLogWriter::~ControllerLogWriter() = default;
ControllerLogWriter::ControllerLogWriter(ControllerLogWriter&&) noexcept = default;
ControllerLogWriter& ControllerLogWriter::operator=(ControllerLogWriter&&) noexcept = default;

void ControllerLogWriter::Write(const StabilityInput& in) {
  if (!std::isfinite(in.t))
    throw std::invalid_argument("controller log " + impl_->file.path() + ": row " +
                                std::to_string(impl_->rows + 1) + ": t is not finite");
  if (in.t < impl_->last_t)
    throw std::invalid_argument("controller log " + impl_->file.path() + ": row " +
                                std::to_string(impl_->rows + 1) + ": t goes backwards");
  std::string& r = impl_->row;
  r.clear();
  for (std::size_t i = 0; i < kInputColumns.size(); ++i) {
    const LogColumn& c = kInputColumns[i];
    if (i) r += ',';
    if (c.integer != nullptr)
      detail::AppendInteger(&r, in.*c.integer);
    else if (c.wheel != nullptr)
      detail::AppendNumber(&r, (in.*c.wheel)[c.wheel_index]);
    else
      detail::AppendNumber(&r, in.*c.real);
  }
  r += '\n';
  impl_->file.Append(r);
  impl_->bytes += static_cast<std::int64_t>(r.size());
  impl_->last_t = in.t;
  ++impl_->rows;
}

void ControllerLogWriter::Write(const StabilityInput& in, const controller::StabilityOutput& out) {
  if (!out.valid) {
    Write(in);
    return;
  }
  StabilityInput with_loads = in;
  with_loads.fz_external = out.fz;
  Write(with_loads);
}

void ControllerLogWriter::Commit() { impl_->file.Commit(); }

const std::string& ControllerLogWriter::path() const noexcept { return impl_->file.path(); }
std::int64_t ControllerLogWriter::rows() const noexcept { return impl_->rows; }
std::int64_t ControllerLogWriter::bytes() const noexcept { return impl_->bytes; }
bool ControllerLogWriter::is_file() const noexcept {
  return impl_->file.mode() == io::AtomicWriter::Mode::kReplace;
}

// ---------------------------------------------------------------------------------------------
// ControllerLogReader

ControllerLogReader::ControllerLogReader(const std::string& path) : path_(path) {
  file_.open(path, std::ios::binary);
  if (!file_)
    throw LogFormatError(path, 0, "",
                         std::string("cannot open the log (") + std::strerror(errno) + ")");
  line_no_ = 1;
  if (!std::getline(file_, buffer_)) {
    std::string expected;
    for (const auto& c : kInputColumns)
      if (c.required) expected += (expected.empty() ? "" : ",") + std::string(c.name);
    throw LogFormatError(path, 1, "",
                         "empty file; expected a header row with at least the columns " + expected);
  }
  std::string_view text(buffer_);
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte-order mark
  if (const std::string bad = BinaryByte(text); !bad.empty())
    throw LogFormatError(path, 1, "",
                         bad +
                             ": this is a binary file, not a CSV controller log (scw replay "
                             "--columns lists the format)");

  // Problems of the header, each kind in one message however many columns it concerns: a file
  // with other columns altogether (another CSV) is one line, not one line per column.
  std::vector<std::string> unknown, unknown_hint, missing;
  std::vector<bool> unknown_empty;
  std::vector<Problem> problems;
  std::string first_column;
  // `column` is the one the problem concerns (LogFormatError::column() of the first problem);
  // a problem about several columns (`column` empty) names them in its message.
  auto add = [&](const std::string& column, const std::string& message) {
    if (problems.empty()) first_column = column;
    problems.push_back({LinePath(1, column), message});
  };
  std::vector<bool> seen(kInputColumns.size(), false);
  std::vector<std::string> seen_as(kInputColumns.size());  // spelling in the header
  std::size_t known = 0;
  std::size_t pos = 0;
  while (true) {
    const std::size_t comma = text.find(',', pos);
    const std::string name(Trim(
        text.substr(pos, comma == std::string_view::npos ? std::string_view::npos : comma - pos)));
    header_.push_back(ColumnName(name));
    const auto it =
        std::find_if(kInputColumns.begin(), kInputColumns.end(), [&](const LogColumn& c) {
          return c.name == name || (!c.alias.empty() && c.alias == name);
        });
    if (it == kInputColumns.end()) {
      unknown.push_back(name.empty() ? "#" + std::to_string(header_.size()) : header_.back());
      unknown_empty.push_back(name.empty());
      unknown_hint.push_back(Suggest(name));
      column_of_cell_.push_back(-1);
    } else {
      ++known;
      const auto idx = static_cast<std::size_t>(it - kInputColumns.begin());
      if (seen[idx])
        add(name, seen_as[idx] == name
                      ? "column given twice in the header"
                      : "column given twice in the header (as " + seen_as[idx] + " and as " + name +
                            ", " + std::string(it->alias) + " being the old name of " +
                            std::string(it->name) + ")");
      seen[idx] = true;
      seen_as[idx] = name;
      if (it->real == &StabilityInput::t) t_column_ = name;
      column_of_cell_.push_back(static_cast<int>(idx));
    }
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  std::size_t required = 0;
  for (std::size_t i = 0; i < kInputColumns.size(); ++i) {
    if (!kInputColumns[i].required) continue;
    ++required;
    if (!seen[i]) missing.push_back(std::string(kInputColumns[i].name));
  }
  constexpr const char* kColumnsHint = "scw replay --columns lists every column with its unit";
  if (known == 0) {
    // Not a controller log at all: say so once, with what a log has.
    std::vector<std::string> names;
    for (const auto& c : kInputColumns)
      if (c.required) names.emplace_back(c.name);
    add("", "not a controller log header: none of its " + std::to_string(header_.size()) +
                " column(s) (" + NameList(unknown, 4) + ") is a log column; a log needs the " +
                std::to_string(required) + " required columns " + NameList(names, 6) + " (" +
                kColumnsHint + ")");
    throw LogFormatError(path, std::move(problems), "");
  }
  if (unknown.size() <= 3) {
    for (std::size_t i = 0; i < unknown.size(); ++i) {
      std::string msg = unknown_empty[i] ? "empty column name in the header"
                                         : "unknown column '" + unknown[i] + "'";
      if (!unknown_hint[i].empty()) msg += " (did you mean " + unknown_hint[i] + "?)";
      add(unknown[i], msg);
    }
  } else {
    add("", std::to_string(unknown.size()) + " unknown columns: " + NameList(unknown, 5) + " (" +
                kColumnsHint + ")");
  }
  if (missing.size() == 1) {
    const LogColumn& c = *std::find_if(kInputColumns.begin(), kInputColumns.end(),
                                       [&](const LogColumn& x) { return x.name == missing[0]; });
    add(missing[0],
        "required column is missing from the header (write nan in its cells if the "
        "signal was not recorded" +
            (c.alias.empty() ? std::string(")")
                             : "; the old name " + std::string(c.alias) + " is read too)"));
  } else if (missing.size() > 1) {
    add("", std::to_string(missing.size()) + " of the " + std::to_string(required) +
                " required columns are missing from the header: " + NameList(missing, 6) +
                " (write nan in a column's cells if the signal was not recorded; " + kColumnsHint +
                ")");
  }
  if (!problems.empty()) throw LogFormatError(path, std::move(problems), first_column);
}

void ControllerLogReader::Fail(const std::string& column, const std::string& message) const {
  throw LogFormatError(path_, line_no_, column, message);
}

bool ControllerLogReader::Next(StabilityInput* in) {
  const auto at_end = [&] {
    if (file_.bad()) {
      ++line_no_;
      Fail("", std::string("read error (") + std::strerror(errno) + ")");
    }
    if (rows_ == 0) {
      ++line_no_;
      Fail("", "no data rows after the header (a log needs at least one controller step)");
    }
    return false;
  };
  if (!std::getline(file_, buffer_)) return at_end();
  ++line_no_;
  if (Trim(buffer_).empty()) {
    // Blank lines are tolerated only at the end of the file (editors and tools append them).
    const std::int64_t blank = line_no_;
    while (std::getline(file_, buffer_)) {
      ++line_no_;
      if (!Trim(buffer_).empty()) {
        line_no_ = blank;
        Fail("", "empty line; every row needs " + std::to_string(column_of_cell_.size()) +
                     " cells (one per header column)");
      }
    }
    line_no_ = blank - 1;
    return at_end();
  }
  const std::string_view text(buffer_);
  const std::size_t cells = static_cast<std::size_t>(std::count(text.begin(), text.end(), ',')) + 1;
  const std::size_t expected = column_of_cell_.size();
  if (cells != expected) {
    if (cells < expected)
      Fail(header_[cells], "row has " + std::to_string(cells) + " cells, the header has " +
                               std::to_string(expected) +
                               " columns (first missing column: " + header_[cells] + ")");
    Fail(header_.back(), "row has " + std::to_string(cells) + " cells, the header has " +
                             std::to_string(expected) + " columns (extra cells after column " +
                             header_.back() + ")");
  }

  *in = StabilityInput{};
  std::size_t pos = 0;
  for (std::size_t k = 0; k < expected; ++k) {
    const std::size_t comma = k + 1 < expected ? text.find(',', pos) : text.size();
    const std::string_view cell = Trim(text.substr(pos, comma - pos));
    pos = comma + 1;
    const LogColumn& c = kInputColumns[static_cast<std::size_t>(column_of_cell_[k])];
    if (c.integer != nullptr) {
      if (!ParseInteger(cell, &(in->*c.integer)))
        Fail(header_[k], cell.empty() || IsNanText(cell)
                             ? "missing value; gear columns need an integer in every row"
                             : "expected an integer, got " + Quote(cell));
      continue;
    }
    double v = 0.0;
    if (!ParseReal(cell, &v))
      Fail(header_[k], "not a number: " + Quote(cell) +
                           " (write nan or leave the cell "
                           "empty for a missing value)");
    if (c.wheel != nullptr)
      (in->*c.wheel)[c.wheel_index] = v;
    else
      in->*c.real = v;
  }
  if (!std::isfinite(in->t)) Fail(t_column_, "the time stamp must be a finite number in every row");
  if (rows_ > 0 && in->t < last_t_) {
    std::string a, b;
    detail::AppendNumber(&a, in->t);
    detail::AppendNumber(&b, last_t_);
    Fail(t_column_, "time goes backwards: t = " + a + " s after t = " + b + " s on line " +
                        std::to_string(line_no_ - 1));
  }
  last_t_ = in->t;
  ++rows_;
  return true;
}

}  // namespace scw::tuning::replay
