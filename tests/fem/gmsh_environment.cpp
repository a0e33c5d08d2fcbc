#include "gmsh_reference.h"

namespace {
// Gmsh is initialised once for all tests of the program and finalised at the end.
[[maybe_unused]] auto* const gmsh_environment =
    ::testing::AddGlobalTestEnvironment(new shellflow::fem::testing::GmshEnvironment);
}  // namespace
