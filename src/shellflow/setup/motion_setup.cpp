#include "shellflow/setup/motion_setup.h"

namespace shellflow::setup {

motion::SpaceMeshOptions space_mesh_options(const io::MotionSection& m) {
  motion::SpaceMeshOptions options;
  options.interface_groups = m.interface_groups;
  options.fixed_groups = m.fixed_groups;
  options.sliding_groups = m.sliding_groups;
  options.interface_exponent = m.interface_exponent;
  options.fixed_exponent = m.fixed_exponent;
  options.weighting = m.weighting == io::MotionWeighting::area ? motion::IdwWeighting::area
                                                               : motion::IdwWeighting::plain;
  return options;
}

}  // namespace shellflow::setup
