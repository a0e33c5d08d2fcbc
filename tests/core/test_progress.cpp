#include <gtest/gtest.h>

#include "shellflow/core/progress.h"

using shellflow::Progress;

TEST(Progress, LineShowsTimeStepFractionAndEta) {
  const Progress progress(0.0, 0.14, false);
  // A quarter of the way after 10 s of wall time: 30 s remain.
  EXPECT_EQ(progress.line(0.035, 350, 10.0), "t = 3.500e-02 s  step 350   25.0 %  ETA 00:00:30");
  // Hours and minutes.
  EXPECT_EQ(progress.line(0.014, 140, 400.0), "t = 1.400e-02 s  step 140   10.0 %  ETA 01:00:00");
}

TEST(Progress, EtaUnknownAtTheStartAndFractionClamped) {
  const Progress progress(1.0, 2.0, false);
  EXPECT_EQ(progress.line(1.0, 0, 0.0), "t = 1.000e+00 s  step 0    0.0 %  ETA --:--:--");
  EXPECT_EQ(progress.line(2.5, 10, 5.0), "t = 2.500e+00 s  step 10  100.0 %  ETA 00:00:00");
}
