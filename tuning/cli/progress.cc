#include "tuning/cli/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace scw::cli {
namespace {

// Redraws on a terminal at most this often; lines into a file or pipe at most this often.
constexpr double kTerminalPeriodS = 0.1;
constexpr double kLogPeriodS = 5.0;

std::string Whole(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f", std::floor(x + 1e-9));
  return buf;
}

}  // namespace

CLI::Option* AddProgressOption(CLI::App* cmd, std::string* value) {
  return cmd
      ->add_option("--progress", *value,
                   "Progress line on stderr (phase, done/total, elapsed, eta): auto (only on a "
                   "terminal), always, never")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "always", "never"}));
}

ProgressMode ParseProgressMode(const std::string& text) {
  if (text == "always") return ProgressMode::kAlways;
  if (text == "never") return ProgressMode::kNever;
  return ProgressMode::kAuto;
}

std::string FormatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) return "-";
  char buf[48];
  const long s = std::lround(seconds);
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%ld s", s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%ld min %02ld s", s / 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  return buf;
}

ProgressLine::ProgressLine(ProgressMode mode) : start_(std::chrono::steady_clock::now()) {
  terminal_ = ::isatty(2) != 0;
  enabled_ = mode == ProgressMode::kAlways || (mode == ProgressMode::kAuto && terminal_);
}

ProgressLine::~ProgressLine() { Finish(); }

std::string ProgressLine::Render(const ProgressUpdate& u, double now_s) const {
  std::string s = "  " + u.phase + "  " + Whole(u.done) + "/" + Whole(u.total);
  if (!u.unit.empty()) s += " " + u.unit;
  s += "  elapsed " + FormatDuration(now_s);
  double eta = u.eta_s;
  if (eta < 0.0) {
    const double in_phase = now_s - phase_start_s_;
    eta = u.done > 0.0 && u.total >= u.done ? in_phase / u.done * (u.total - u.done) : -1.0;
  }
  s += "  eta " + FormatDuration(eta);
  if (!u.detail.empty()) s += "  " + u.detail;
  return s;
}

void ProgressLine::Print(const std::string& text) {
  if (terminal_) {
    // Redraw in place; blanks clear what a longer previous line left.
    std::string line = "\r" + text;
    if (text.size() < last_width_) line.append(last_width_ - text.size(), ' ');
    last_width_ = text.size();
    std::fputs(line.c_str(), stderr);
    line_open_ = true;
  } else {
    std::fputs((text + "\n").c_str(), stderr);
  }
  std::fflush(stderr);
}

void ProgressLine::Update(const ProgressUpdate& u) {
  if (!enabled_) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  const double now_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const bool new_phase = u.phase != phase_;
  if (new_phase) {
    phase_ = u.phase;
    phase_start_s_ = now_s;
  }
  pending_ = u;
  pending_shown_ = false;
  const double period = terminal_ ? kTerminalPeriodS : kLogPeriodS;
  // The first update of a phase and the one completing it show at once (once: the total of a
  // simulation is an estimate the run may pass).
  const bool completes = u.total > 0.0 && u.done >= u.total && last_done_shown_ < u.total;
  if (!new_phase && !completes && now_s - last_print_s_ < period) return;
  Print(Render(u, now_s));
  last_print_s_ = now_s;
  last_done_shown_ = u.done;
  pending_shown_ = true;
}

void ProgressLine::Finish() {
  if (!enabled_) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!pending_shown_) {
    const double now_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    Print(Render(pending_, now_s));
    pending_shown_ = true;
    last_done_shown_ = pending_.done;
  }
  if (line_open_) {
    std::fputs("\n", stderr);
    std::fflush(stderr);
    line_open_ = false;
    last_width_ = 0;
  }
}

}  // namespace scw::cli
