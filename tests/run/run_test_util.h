#pragma once
// Shared pieces of the run-layer tests: a scratch folder and a small tetrahedral cube.
#include <filesystem>
#include <random>
#include <string>

#include "shellflow/mesh/mesh.h"

namespace shellflow::run::test {

/// A fresh folder under the system's temporary folder, removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() / ("shellflow_run_test_" + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// The whole content of a file.
std::string read_file(const std::filesystem::path& p);

/// The cube [0, 2]^3 in 2 x 2 x 2 Kuhn cubes of 6 tetrahedra each (tests/support/box_mesh.h),
/// named `name`, with the group "bottom" of the faces on z = 0.
mesh::Mesh cube_mesh(const std::string& name);

}  // namespace shellflow::run::test
