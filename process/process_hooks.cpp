#include "process/process_hooks.h"

#include "engine/solvers/ipopt/dense_kkt.h"

namespace bristle {

void installProcessHooks() { installDenseKktSolver(); }

}  // namespace bristle
