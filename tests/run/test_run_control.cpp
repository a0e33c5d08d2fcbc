// RunControl: when checkpoints are due, a stop request, and a restart that puts the writers
// and the state back to the checkpoint.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "run_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/run/run_control.h"

namespace shellflow::run {
namespace {

using test::read_file;
using test::TempDir;

io::Case a_case() {
  io::Case c;
  c.name = "control_test";
  c.output.checkpoint_every = 3;
  return c;
}

TEST(RunControl, CheckpointsDueEveryN) {
  TempDir dir;
  const io::Case c = a_case();
  RunControl control(c, dir.path(), {}, std::nullopt, {});
  EXPECT_FALSE(control.checkpoint_due(1));
  EXPECT_TRUE(control.checkpoint_due(3));
  EXPECT_TRUE(control.checkpoint_due(6));
  EXPECT_FALSE(control.checkpoint_due(7));
  EXPECT_FALSE(control.restarting());
  EXPECT_EQ(control.first_step(), 1);
}

TEST(RunControl, StopAfterNSteps) {
  TempDir dir;
  const io::Case c = a_case();
  RunControl control(c, dir.path(), {.stop_after = 2, .stop_at_wall = {}, .restart = {}}, std::nullopt, {});
  EXPECT_FALSE(control.stop_due(1));
  EXPECT_TRUE(control.stop_due(2));
}

TEST(RunControl, RestoreThenContinueEqualsStraightOn) {
  TempDir dir;
  const io::Case c = a_case();
  // A run of 5 steps whose state is a counter; it checkpoints at step 3.
  long state = 0;
  {
    RunControl control(c, dir.path(), {}, std::nullopt, {});
    io::ProbeWriter csv(dir.path() / "probes.csv", {"state"});
    control.add_output(csv);
    control.set_state(
        "counter", [&](ArchiveWriter& out) { out.put(state); }, [&](ArchiveReader& in) { state = in.get<long>(); });
    for (long step = 1; step <= 5; ++step) {
      state += step * step;
      csv.append(double(step), std::vector<double>{double(state)});
      if (control.checkpoint_due(step)) control.write_checkpoint(step, double(step));
    }
  }
  const std::string straight = read_file(dir.path() / "probes.csv");
  const long final_state = state;
  // The restart: the writer cut back to step 3, the state that of step 3, steps 4 and 5 again.
  state = -1;
  RunControl control(c, dir.path(), {}, load_restart(dir.path(), c), {});
  EXPECT_TRUE(control.restarting());
  EXPECT_EQ(control.first_step(), 4);
  io::ProbeWriter csv(dir.path() / "probes.csv", {"state"}, control.output_mode());
  control.add_output(csv);
  control.set_state(
      "counter", [&](ArchiveWriter& out) { out.put(state); }, [&](ArchiveReader& in) { state = in.get<long>(); });
  control.restore();
  EXPECT_EQ(state, 1 + 4 + 9);
  for (long step = control.first_step(); step <= 5; ++step) {
    state += step * step;
    csv.append(double(step), std::vector<double>{double(state)});
  }
  EXPECT_EQ(state, final_state);
  EXPECT_EQ(read_file(dir.path() / "probes.csv"), straight);
}

TEST(RunControl, ACheckpointOfAnotherKindIsRefused) {
  TempDir dir;
  const io::Case c = a_case();
  {
    RunControl control(c, dir.path(), {}, std::nullopt, {});
    control.set_state(
        "flow", [](ArchiveWriter&) {}, [](ArchiveReader&) {});
    control.write_checkpoint(3, 3.0);
  }
  RunControl control(c, dir.path(), {}, load_restart(dir.path(), c), {});
  control.set_state(
      "shell dynamics", [](ArchiveWriter&) {}, [](ArchiveReader&) {});
  EXPECT_THROW(control.restore(), Error);
}

}  // namespace
}  // namespace shellflow::run
