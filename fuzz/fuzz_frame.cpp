// libFuzzer target. Frames: .npz bytes -> Frame or FormatError (sluice::frame_from_npz, used by render and analyze), as given
// and with the zip CRCs fixed, then the write-back round trip.
// See fuzz/targets.hpp for the contract and docs/hardening.md for how to run it.
#include <cstddef>
#include <cstdint>
#include <string>

#include "targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sluice::fuzz::check_frame(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
