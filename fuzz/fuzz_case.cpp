// libFuzzer target. Case files: TOML text -> a validated Case or CaseError (sluice::parse_case), then the template round trip.
// See fuzz/targets.hpp for the contract and docs/hardening.md for how to run it.
#include <cstddef>
#include <cstdint>
#include <string>

#include "targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sluice::fuzz::check_case(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
