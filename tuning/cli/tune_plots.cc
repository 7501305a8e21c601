#include "tuning/cli/tune_plots.h"

#include <system_error>

#include "tuning/cli/python_script.h"
#include "tuning/cli/tune_plots_script.h"  // generated: generated::kTunePlotScript

namespace scw::cli {

std::string_view TunePlotScript() { return generated::kTunePlotScript; }

std::string TunePlotsMarkdown() {
  return std::string("### Plots\n\n") + "![Convergence: training cost of every evaluation and " +
         "the best cost so far, optimiser phases marked](" + kConvergencePlotFile + ")\n\n" +
         "![Baseline vs tuned per scenario: how the run ended, mean lap time, max sideslip, " +
         "interventions](" + kComparisonPlotFile + ")\n\n";
}

bool WriteTunePlots(const std::filesystem::path& run_dir, std::string* message,
                    const TunePlotOptions& options) {
  try {
    if (!RunPythonScript(TunePlotScript(), {run_dir.string()}, message,
                         {options.python, "tune_plots: "}))
      return false;
    for (const char* f : {kConvergencePlotFile, kComparisonPlotFile}) {
      std::error_code ec;
      if (std::filesystem::file_size(run_dir / f, ec) == 0 || ec) {
        if (message) *message = "the plot script did not write " + (run_dir / f).string();
        return false;
      }
    }
    return true;
  } catch (const std::exception& e) {
    if (message) *message = std::string("cannot draw the plots: ") + e.what();
  } catch (...) {
    if (message) *message = "cannot draw the plots";
  }
  return false;
}

bool WriteFrontPlot(const std::filesystem::path& front_dir, std::string* message,
                    const TunePlotOptions& options) {
  try {
    if (!RunPythonScript(TunePlotScript(), {"--front", front_dir.string()}, message,
                         {options.python, "tune_plots: "}))
      return false;
    std::error_code ec;
    if (std::filesystem::file_size(front_dir / kFrontPlotFile, ec) == 0 || ec) {
      if (message)
        *message = "the plot script did not write " + (front_dir / kFrontPlotFile).string();
      return false;
    }
    return true;
  } catch (const std::exception& e) {
    if (message) *message = std::string("cannot draw the front: ") + e.what();
  }
  return false;
}

}  // namespace scw::cli
