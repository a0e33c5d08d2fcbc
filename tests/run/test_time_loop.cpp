// The one time loop: which steps record probes and frames, the failure path that writes the
// last valid state once, a stop with a checkpoint.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "shellflow/core/error.h"
#include "shellflow/run/time_loop.h"

namespace shellflow::run {
namespace {

using Calls = std::vector<std::pair<long, Record>>;

Calls run_loop(long steps, int every, long fail_at = -1) {
  Calls calls;
  double t = 0.0;
  run_time_loop(
      {steps, every, double(steps), "out", {}},
      [&](long step) {
        if (step == fail_at) throw SolverError("boom");
        t = double(step);
        return t;
      },
      [&](long step, Record what) { calls.emplace_back(step, what); }, [&] { return t; });
  return calls;
}

TEST(TimeLoop, ProbesEveryStepFramesEveryNAndAtTheLast) {
  const Calls calls = run_loop(7, 3);
  const Calls expected = {{1, Record::probes},           {2, Record::probes}, {3, Record::probes_and_fields},
                          {4, Record::probes},           {5, Record::probes}, {6, Record::probes_and_fields},
                          {7, Record::probes_and_fields}};
  EXPECT_EQ(calls, expected);
}

TEST(TimeLoop, UntilMoreSaysNo) {
  Calls calls;
  double t = 0.0;
  const long last = run_time_loop(
      {0, 2, 1.0, "out", [&](long) { return t < 0.5; }}, [&](long) { return t += 0.2; },
      [&](long step, Record what) { calls.emplace_back(step, what); }, [&] { return t; });
  EXPECT_EQ(last, 3);  // 0.2, 0.4, 0.6
  ASSERT_EQ(calls.size(), 3u);
  EXPECT_EQ(calls.back(), std::make_pair(3L, Record::probes_and_fields));
}

TEST(TimeLoop, FailureWritesTheLastValidStateOnce) {
  Calls calls;
  try {
    calls = {};
    double t = 0.0;
    run_time_loop(
        {10, 3, 10.0, "the_folder", {}},
        [&](long step) {
          if (step == 5) throw SolverError("negative pressure");
          return t = double(step);
        },
        [&](long step, Record what) { calls.emplace_back(step, what); }, [&] { return t; });
    FAIL() << "no error";
  } catch (const SolverError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("negative pressure (step 5)"), std::string::npos) << what;
    EXPECT_NE(what.find("the last valid state (t = 4 s) is in the_folder"), std::string::npos) << what;
  }
  // Step 4 had its probe row, not its frame: the frame of step 4 follows, once.
  ASSERT_FALSE(calls.empty());
  EXPECT_EQ(calls.back(), std::make_pair(4L, Record::fields));
  EXPECT_EQ(std::count(calls.begin(), calls.end(), std::make_pair(4L, Record::fields)), 1);
}

TEST(TimeLoop, FailureRightAfterAFrameWritesNothingMore) {
  Calls calls;
  EXPECT_THROW(
      {
        double t = 0.0;
        run_time_loop(
            {10, 3, 10.0, "out", {}},
            [&](long step) {
              if (step == 4) throw SolverError("diverged");
              return t = double(step);
            },
            [&](long step, Record what) { calls.emplace_back(step, what); }, [&] { return t; });
      },
      SolverError);
  ASSERT_EQ(calls.size(), 3u);
  EXPECT_EQ(calls.back(), std::make_pair(3L, Record::probes_and_fields));
}

}  // namespace
}  // namespace shellflow::run
