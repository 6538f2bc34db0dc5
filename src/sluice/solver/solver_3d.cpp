#include "sluice/solver/solver_impl.hpp"

namespace sluice {
template class Solver<3>;
}  // namespace sluice
