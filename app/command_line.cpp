// What the subcommands' option definitions share (commands.h): the case and its --set
// overrides, the output folder and plots, finite numbers.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "commands.h"
#include "shellflow/io/checkpoint.h"

namespace shellflow::app {

void add_case_options(CLI::App* sub, CommonOptions& common) {
  sub->add_option("case", common.case_file, "Case file (YAML); see docs/case-format.md")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("--set", common.overrides,
                  "KEY=VALUE: replace a key of the case file (dotted path, YAML value), e.g. --set "
                  "fluid.free_stream.mach=2.1 --set time.end=0.05; repeatable")
      ->allow_extra_args(false)
      ->take_all();
}

void add_output_options(CLI::App* sub, CommonOptions& common) {
  sub->add_option("-o,--output", common.output_dir,
                  "Output directory (default: the case's output.directory, else out/<name>)");
  sub->add_flag("!--no-plot", common.plot, "Do not make the PNG plots at the end");
}

const CLI::Validator& finite_number() {
  // nan and inf pass CLI::PositiveNumber (nan <= 0 is false): numbers of the command line are finite.
  static const CLI::Validator finite(
      [](std::string& text) {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        return std::isfinite(x) ? std::string() : std::string("must be a finite number");
      },
      "FINITE");
  return finite;
}

std::string read_text_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool has_checkpoint(const std::filesystem::path& dir) {
  std::error_code ec;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!name.ends_with(".tmp") && io::is_checkpoint_name(name)) return true;
  }
  return false;
}

}  // namespace shellflow::app
