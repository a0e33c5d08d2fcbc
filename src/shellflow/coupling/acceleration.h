#pragma once
// Acceleration of the coupling fixed point x = H(x) inside a shell step (docs/coupling.md,
// "Implicit coupling"). x is the load vector the shell step is made with (the pressure rise
// at the shell's load points), H(x) the loads the flow gives back at the end of the step
// after the shell moved under x. Iteration k has applied x^k and got x~^k = H(x^k), residual
// r^k = x~^k - x^k; the acceleration chooses x^{k+1}:
//   none       x^{k+1} = x~^k                      (plain fixed point, relaxation 1)
//   constant   x^{k+1} = x^k + w r^k
//   aitken     the same with Aitken's dynamic w_k = -w_{k-1} r^{k-1}.(r^k - r^{k-1}) / |r^k - r^{k-1}|^2
//   iqn_ils    interface quasi-Newton with an inverse Jacobian from least squares
//              (Degroote et al. 2009): V = [r^k - r^{k-1} ...], W = [x~^k - x~^{k-1} ...],
//              c = argmin |V c + r^k|, x^{k+1} = x~^k + W c; columns of `reuse` past windows
//              join the current window's, near-dependent columns are filtered out (QR).
// All inner products are weighted (the load points' reference areas): the norms are those of
// the pressure field on the shell, independent of how the load points are distributed.
// A vector of several blocks (the pressure, then the shear of a viscous flow: values five
// orders of magnitude apart) is scaled per block in the inner products of aitken and iqn_ils,
// each block by 1/|H(x^0)_b| of the window's first iteration (preCICE's "value"
// preconditioner), so that the small block is not lost in the least squares; with one block
// nothing is scaled.
#include <deque>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "shellflow/core/archive.h"

namespace shellflow::coupling {

enum class AccelerationType { none, constant, aitken, iqn_ils };
std::string_view to_string(AccelerationType t);

struct AccelerationOptions {
  AccelerationType type = AccelerationType::none;
  /// constant: w; aitken: the first iteration's w (and the cap of the carried-over w);
  /// iqn_ils: w of the first iteration of the run (no columns yet).
  double relaxation = 0.5;
  int columns = 100;      ///< iqn_ils: most columns used (newest first)
  int reuse = 8;          ///< iqn_ils: past windows (shell steps) whose columns are reused
  double filter = 1e-10;  ///< iqn_ils: a column is dropped when its part orthogonal to the newer
                          ///< ones is below filter x its norm (QR1 filter)
};

class Acceleration {
 public:
  virtual ~Acceleration() = default;
  /// A new window (shell step) starts: the iterations of the last one are forgotten
  /// (iqn_ils keeps its columns as one of the reused windows).
  virtual void begin_window() {}
  /// Iteration k: `x` holds x^k on entry and x^{k+1} on return; `fx` is x~^k = H(x^k).
  virtual void update(std::span<double> x, std::span<const double> fx) = 0;
  /// The window converged (its state at the end of the step is the one kept).
  virtual void end_window() {}
  /// Checkpoint of what carries over between windows (bit-exact restart).
  virtual void save(ArchiveWriter&) const {}
  virtual void restore(ArchiveReader&) {}
};

/// `weight`: one non-negative weight per entry (the load points' areas); the object keeps a copy.
/// `blocks`: the sizes of the vector's blocks, in order, summing to its size (empty: one block).
std::unique_ptr<Acceleration> make_acceleration(const AccelerationOptions& options, std::vector<double> weight,
                                                std::vector<std::size_t> blocks = {});

/// Weighted norm sqrt(sum w_k v_k^2).
double weighted_norm(std::span<const double> v, std::span<const double> weight);

/// Per entry, 1/|v_b|_w of its block b of `v` (1 where a block is zero): the block scaling.
std::vector<double> block_scale(std::span<const double> v, std::span<const double> weight,
                                std::span<const std::size_t> blocks);

}  // namespace shellflow::coupling
