// Test-only fault injection: a named point of the program raises a signal in its own process at
// its K-th pass, so that tests of interruption and of a dying MPI rank inject the fault at a
// defined point instead of racing a timer (docs/robustness.md#fault-injection-in-tests).
//
//   SCW_TEST_FAULT=POINT:K:SIGNAL     e.g. worker-job:3:KILL, tune-eval:2:INT, tune-screen:1:INT,
//   simulate-step:500:TERM
//
// POINT names the place (the callers below), K ≥ 1 counts its passes in this process, SIGNAL is one
// of INT, TERM, KILL. Unset (the normal case) or naming another point: nothing happens. A value
// that does not parse is reported once on stderr and ignored. The points:
//   worker-job     an MPI worker rank has received its K-th job (before running it);
//   tune-eval      scw tune has logged its K-th evaluation (evaluation 0 is the first);
//   tune-screen    scw tune's screen (before the search) has finished its K-th run;
//   simulate-step  scw simulate's stability controller has run its K-th step (100 Hz).
#pragma once

#include <string_view>

namespace scw::io {

/// Call at each pass of `point` with the pass number (1, 2, ...): raises the signal that
/// $SCW_TEST_FAULT names when it names this point and this pass. Thread-safe; async-signal-safe
/// only in that it reads the environment once, on the first call.
void TestFaultPoint(std::string_view point, long pass);

}  // namespace scw::io
