// One of the four parts of the pair loop, compiled side by side (physics/pair_loop.cpp puts their
// tables together): the 3D loops with pairs in single precision, for every instruction set Highway
// targets here.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "sluice/physics/pair_loop_3d_single.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include "sluice/physics/pair_loop-inl.hpp"

HWY_BEFORE_NAMESPACE();
namespace sluice::HWY_NAMESPACE {
template void add_loops<3, float>(DimensionLoops<3>&);
}  // namespace sluice::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();
