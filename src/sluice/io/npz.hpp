// NumPy .npz files: a zip archive (stored, uncompressed) of .npy arrays, readable with plain
// numpy.load and no pickle. Written and read by hand: the format is small and fully specified
// (NEP 1 for .npy, PKWARE APPNOTE for zip); tests read our files back with real numpy.
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace sluice {

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

// Serialises named arrays (insertion order kept) into .npz bytes.
std::string make_npz(const std::vector<std::pair<std::string, NpyArray>>& arrays);

// Parses .npz bytes written by make_npz (stored entries). Throws FormatError naming what is wrong.
std::map<std::string, NpyArray> parse_npz(const std::string& bytes);

template <class T>
std::string npy_dtype();

}  // namespace sluice
