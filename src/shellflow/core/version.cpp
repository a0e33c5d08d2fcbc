#include "shellflow/core/version.h"
