// libFuzzer target. Meshes: bytes -> a closed triangle mesh or MeshError (sluice::read_mesh, as STL or
// OBJ, then check_closed_mesh and the solid's queries). See fuzz/targets.hpp for the contract and
// docs/hardening.md for how to run it.
#include <cstddef>
#include <cstdint>
#include <string>

#include "targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sluice::fuzz::check_mesh(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
