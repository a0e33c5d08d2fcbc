#include "shellflow/core/version.h"

namespace shellflow {
const char* const source_dir = SHELLFLOW_SOURCE_DIR;
}  // namespace shellflow
