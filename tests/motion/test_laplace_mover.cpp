// Tests of the Laplacian-smoothing baseline mover (motion/laplace_mover.h).
#include <gtest/gtest.h>
