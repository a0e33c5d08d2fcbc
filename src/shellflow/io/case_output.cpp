// The `output` section of a case file: where and how often the run writes its results.
#include <string>

#include "shellflow/io/case_sections.h"

namespace shellflow::io::detail {

namespace fs = std::filesystem;

OutputSection read_output(const YamlNode& root, const std::string& case_name) {
  OutputSection out;
  out.directory = fs::path("out") / case_name;
  if (auto node = root.optional_child("output")) {
    if (auto dir = node->maybe<std::string>("directory")) {
      if (dir->empty()) node->fail("directory", "expected a directory name, got an empty string");
      out.directory = *dir;
    }
    out.every = node->optional<int>("every", 1, Range::at_least(1));
    out.checkpoint_every = node->optional<long>("checkpoint_every", 0, Range::non_negative());
    out.shell_stress = read_enum(*node, "shell_stress", kShellStresses, OutputSection::ShellStress::cauchy);
    node->finish();
  }
  return out;
}

}  // namespace shellflow::io::detail
