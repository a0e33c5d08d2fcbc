#pragma once
// A point of the shell mid-surface in parametric form (element, xi1, xi2): the currency of
// the point queries (shell_queries.h) and of the model's load points (shell_model.h).
#include "shellflow/core/types.h"

namespace shellflow::shell {

/// A point of the mid-surface in parametric form.
struct ShellPoint {
  Index element = 0;
  Vec2 xi = Vec2::Zero();
};

}  // namespace shellflow::shell
