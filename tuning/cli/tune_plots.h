// Figures of a `scw tune` run folder, drawn by the CLI with Python and matplotlib (the optimiser
// library writes the data, tuning/cli draws: STYLE.md §2).
//
//   convergence.png  training cost of every evaluation (log scale; colour = optimiser phase from
//                    the log's `phase` column: start, then e.g. crs2 and sbplx; marker = whether
//                    the training runs completed, aborted or the set was rejected), the best cost
//                    so far, phase boundaries; below, the best cost so far on a linear scale
//   comparison.png   per scenario (training, then held-out) and parameter set (baseline, tuned):
//                    how the run ended, mean lap time, max |sideslip| and the ESC/CS/ABS/TC
//                    intervention counts, with the change tuned − baseline
//
// Inputs: the run folder's evaluations.csv (the tuner's log) and comparison.csv (ComparisonCsv).
// The script is tuning/cli/tune_plots.py, compiled into the program as text (CMake generates a
// header with it as a raw string literal), so an installed scw needs no checkout; it is run by
// RunPythonScript (python_script.h: interpreter choice, exit codes) as `PYTHON - RUN_DIR`. It
// writes each PNG under a temporary name in the run folder and renames it into place, with the Agg
// backend and no date or software metadata, so the same inputs give byte-identical files (for the
// same matplotlib version).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace scw::cli {

inline constexpr const char* kConvergencePlotFile = "convergence.png";
inline constexpr const char* kComparisonPlotFile = "comparison.png";

struct TunePlotOptions {
  std::string python;  ///< interpreter (a name looked up in PATH, or a path); "" = the default
};

/// Writes convergence.png and comparison.png into `run_dir` (which must hold evaluations.csv and
/// comparison.csv). Returns false, with a one-line reason in `*message` (may be null), when no
/// Python interpreter is found, matplotlib is missing, an input is malformed or the script fails;
/// a figure written before the failure stays. Never throws. On success `*message` is cleared.
/// Blocks while the script runs (a second or two).
bool WriteTunePlots(const std::filesystem::path& run_dir, std::string* message,
                    const TunePlotOptions& options = {});

inline constexpr const char* kFrontPlotFile = "front.png";

/// Writes front.png into `front_dir` (which must hold front.csv); the same contract as
/// WriteTunePlots.
bool WriteFrontPlot(const std::filesystem::path& front_dir, std::string* message,
                    const TunePlotOptions& options = {});

/// Markdown that embeds both figures, for comparison.md in the same folder (relative links).
std::string TunePlotsMarkdown();

/// The embedded script's text.
std::string_view TunePlotScript();

}  // namespace scw::cli
