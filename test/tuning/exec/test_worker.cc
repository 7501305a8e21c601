// A worker process for executor_test.cc: serves the task kind "affine" through the execution
// layer's worker-process protocol (ServeWorkerProcess), as `scw sweep --worker-fd=3` serves
// "sweep". Setup: a factor; batch payload: an offset, the job that throws and the job at which the
// process dies (-1: none). Job i answers factor * i + offset as exact text.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#include "tuning/exec/processes.h"

namespace {

using scw::tuning::exec::WorkerTask;

class Affine final : public WorkerTask {
 public:
  explicit Affine(std::string_view setup) : factor_(std::stod(std::string(setup))) {}
  void StartBatch(std::string_view payload) override {
    if (std::sscanf(std::string(payload).c_str(), "%lf %d %d", &offset_, &throw_at_, &die_at_) != 3)
      throw std::runtime_error("bad payload");
  }
  std::string Run(int index) const override {
    if (index == die_at_) std::_Exit(3);
    if (index == throw_at_) throw std::runtime_error("job " + std::to_string(index) + " failed");
    char buf[64];
    std::snprintf(buf, sizeof buf, "%a", factor_ * index + offset_);
    return buf;
  }

 private:
  double factor_;
  double offset_ = 0.0;
  int throw_at_ = -1, die_at_ = -1;
};

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::strncmp(argv[i], "--worker-fd=", 12) == 0)
      return scw::tuning::exec::ServeWorkerProcess(
          {{"affine", [](std::string_view setup, int) { return std::make_unique<Affine>(setup); }}},
          0, std::atoi(argv[i] + 12));
  std::fprintf(stderr, "usage: %s --worker-fd=N\n", argv[0]);
  return 2;
}
