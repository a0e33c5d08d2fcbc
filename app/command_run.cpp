// `shellflow run`: read the case, hand it to the run library (run/run.h).
#include "commands.h"
#include "shellflow/run/run.h"

namespace shellflow::app {

io::Case read_case(const CommonOptions& options) {
  std::vector<io::KeyOverride> overrides;
  for (const auto& text : options.overrides) overrides.push_back(io::KeyOverride::parse(text));
  return io::read_case(options.case_file, overrides);
}

int run_command(const CommonOptions& options, const StopOptions& stop) {
  const io::Case c = read_case(options);
  return run::run_case(c, {.case_file = options.case_file,
                           .output_dir = options.output_dir,
                           .plot = options.plot,
                           .stop = stop,
                           .ranks = options.ranks});
}

}  // namespace shellflow::app
