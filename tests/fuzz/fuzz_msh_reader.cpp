// Fuzz target: what shellflow runs on a `.msh` file before Gmsh sees it: the structure check
// of mesh/gmsh_input_check (format 4.1 ASCII: $MeshFormat, $PhysicalNames, $Entities,
// $Nodes, $Elements, counts, tags and node references). Gmsh itself is not called.
//
// A shellflow::Error is the expected answer to a damaged file, and its message must be one
// line without control bytes; any other exception, a crash, a hang or a sanitizer report is
// a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_util.h"
#include "shellflow/core/error.h"
#include "shellflow/mesh/gmsh_input_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace shellflow;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    mesh::check_msh_text(text, "fuzz.msh");
  } catch (const Error& e) {
    fuzz::require_one_line(e.what());  // the check's answer to a damaged mesh file
  }
  return 0;
}
