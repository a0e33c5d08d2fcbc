#pragma once
// Saint-Venant–Kirchhoff material, full 3-D isotropic (shell.md §3): no plane-stress
// condensation, no shear correction. The 7th nodal parameter `a` lets the transverse
// strain vary through the thickness, which removes Poisson locking without them.
#include "shellflow/core/error.h"

namespace shellflow::shell {

struct SvkMaterial {
  double young = 0.0;    ///< E
  double poisson = 0.0;  ///< nu, in (-1, 0.5): positive definite isotropic elasticity
  double density = 0.0;  ///< rho_0 (reference configuration); 0 for statics

  double lame_lambda() const { return young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)); }
  double lame_mu() const { return young / (2.0 * (1.0 + poisson)); }

  /// Throws InputError when E <= 0, nu outside (-1, 0.5) or rho < 0.
  void validate() const {
    if (!(young > 0.0)) throw_input_error("shell material: Young's modulus must be > 0 (got {})", young);
    if (!(poisson > -1.0 && poisson < 0.5))
      throw_input_error("shell material: Poisson's ratio must be in (-1, 0.5) (got {})", poisson);
    if (!(density >= 0.0)) throw_input_error("shell material: density must be >= 0 (got {})", density);
  }
};

}  // namespace shellflow::shell
