#include "run_test_util.h"

#include <fstream>
#include <sstream>

#include "support/box_mesh.h"

namespace shellflow::run::test {

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

mesh::Mesh cube_mesh(const std::string& name) {
  mesh::Mesh m = support::box_mesh({2, 2, 2}, Vec3(2, 2, 2),
                                   [](const Vec3& c) { return c.z() == 0.0 ? std::string("bottom") : std::string(); });
  m.name = name;
  m.source = "cube (test)";
  return m;
}

}  // namespace shellflow::run::test
