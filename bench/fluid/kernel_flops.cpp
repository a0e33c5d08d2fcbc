// Floating-point operations of the element kernel per tetrahedron, counted by running the
// kernel (element_kernel.h, written once for a number type) on a number type that counts
// every +, -, *, / and sqrt: the flop figure of the roofline note in docs/fluid.md.
//
//   build/release/bench/fluid/kernel_flops
#include <cstdio>

#include "shellflow/fluid/element_kernel.h"

namespace counting {

inline long adds = 0, muls = 0, divs = 0;

/// A double that counts the operations done with it.
struct Real {
  double v = 0.0;
  Real() = default;
  Real(double x) : v(x) {}  // NOLINT: implicit, as double converts
};
inline Real operator+(Real a, Real b) { return ++adds, Real(a.v + b.v); }
inline Real operator-(Real a, Real b) { return ++adds, Real(a.v - b.v); }
inline Real operator*(Real a, Real b) { return ++muls, Real(a.v * b.v); }
inline Real operator/(Real a, Real b) { return ++divs, Real(a.v / b.v); }
inline Real operator-(Real a) { return Real(-a.v); }
inline Real& operator+=(Real& a, Real b) { return a = a + b; }
inline Real& operator-=(Real& a, Real b) { return a = a - b; }
/// The kernel's rounding barrier does nothing to this type (found by argument lookup).
inline void rounded(Real&) {}

}  // namespace counting

int main() {
  using namespace shellflow::fluid;
  for (const bool moves : {false, true}) {
    detail::KernelConstants k{0.4, 1e-3, true, true, moves};
    detail::ElementData<counting::Real> s;
    s.volume = 1.0 / 6.0;
    for (int a = 0; a < 4; ++a) {
      for (int j = 0; j < 3; ++j) {
        s.grad[a][j] = 0.1 * (a + 1) + j;
        s.w[a][j] = 0.01 * (a - j);
      }
      const double u[num_variables] = {1.0 + 0.1 * a, 0.5, 0.1 * a, -0.2, 2.5 + 0.1 * a};
      for (int v = 0; v < num_variables; ++v) s.u[a][v] = u[v];
    }
    counting::adds = counting::muls = counting::divs = 0;
    detail::compute_element(k, s);
    const long kernel = counting::adds + counting::muls + counting::divs;
    counting::Real value[4][num_variables];
    detail::element_contributions(k, s, counting::Real(0.01), counting::Real(1e-3), counting::Real(1e-3), value);
    const long total = counting::adds + counting::muls + counting::divs;
    std::printf(
        "%s mesh: %ld flops per tetrahedron (compute_element %ld, contributions %ld; "
        "%ld add/sub, %ld mul, %ld div), + 20 adds of the scatter\n",
        moves ? "moving" : "fixed", total, kernel, total - kernel, counting::adds, counting::muls, counting::divs);
  }
  return 0;
}
