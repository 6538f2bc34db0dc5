#include "sluice/solver/solver_impl.hpp"

namespace sluice {
template class Solver<2>;
}  // namespace sluice
