// NumPy .npz files: a zip archive (stored, uncompressed) of .npy arrays, readable with plain
// numpy.load and no pickle. Written and read by hand: the format is small and fully specified
// (NEP 1 for .npy, PKWARE APPNOTE for zip); tests read our files back with real numpy.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sluice {

template <class T>
std::string npy_dtype();
template <>
std::string npy_dtype<double>();
template <>
std::string npy_dtype<float>();
template <>
std::string npy_dtype<std::uint8_t>();
template <>
std::string npy_dtype<std::uint32_t>();
template <>
std::string npy_dtype<std::int64_t>();

struct NpyArray {
  std::string dtype;                 // "<f8", "<u4", "u1", ...
  std::vector<std::size_t> shape;    // {} for a scalar
  std::string bytes;                 // little-endian, C order

  template <class T>
  static NpyArray of(const std::vector<T>& values, std::vector<std::size_t> shape);
  template <class T>
  [[nodiscard]] std::vector<T> values() const;
  [[nodiscard]] std::size_t element_count() const;
};

struct FormatError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The CRC-32 (zip's, zlib's crc32) of `bytes` continued from `crc` (0 to start), for any length:
// zlib takes at most 4 GiB - 1 bytes a call, so longer inputs go in pieces. The .npz entries and the
// checkpoints are checked with it, written and read.
std::uint32_t crc32_of(std::uint32_t crc, std::string_view bytes);

// Where a writer puts its bytes, in order: a file being written (AtomicFile::write) or a string.
using ByteSink = std::function<void(std::string_view)>;

// An array to be written, by reference to bytes held elsewhere (no copy).
struct NpyView {
  std::string dtype;
  std::vector<std::size_t> shape;
  std::string_view bytes;

  template <class T>
  static NpyView of(const std::vector<T>& values, std::vector<std::size_t> shape) {
    return {npy_dtype<T>(), std::move(shape),
            std::string_view(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T))};
  }
};

// Writes named arrays (insertion order kept) as .npz bytes to `out`, as they go: nothing is copied,
// so a frame of a million particles is written without a second copy of it in memory.
void write_npz(const std::vector<std::pair<std::string, NpyView>>& arrays, const ByteSink& out);
// The same, as a string.
std::string make_npz(const std::vector<std::pair<std::string, NpyArray>>& arrays);

// Parses .npz bytes written by make_npz (stored entries). Throws FormatError naming what is wrong.
std::map<std::string, NpyArray> parse_npz(const std::string& bytes);

}  // namespace sluice
