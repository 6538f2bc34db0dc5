// libFuzzer target. Checkpoints: bytes -> Checkpoint or FormatError (sluice::parse_checkpoint), as given and with the CRC fixed.
// See fuzz/targets.hpp for the contract and docs/hardening.md for how to run it.
#include <cstddef>
#include <cstdint>
#include <string>

#include "targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sluice::fuzz::check_checkpoint(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
