#include "sluice/io/npz.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cctype>
#include <cstring>
#include <string_view>

#include "sluice/case/value_text.hpp"

namespace sluice {

static_assert(std::endian::native == std::endian::little, "sluice writes little-endian files");

std::uint32_t crc32_of(std::uint32_t crc, std::string_view bytes) {
  constexpr std::size_t chunk = std::size_t{1} << 30;
  for (std::size_t at = 0; at < bytes.size(); at += chunk) {
    const std::size_t n = std::min(chunk, bytes.size() - at);
    crc = static_cast<std::uint32_t>(crc32(crc, reinterpret_cast<const Bytef*>(bytes.data() + at), static_cast<uInt>(n)));
  }
  return crc;
}

template <>
std::string npy_dtype<double>() { return "<f8"; }
template <>
std::string npy_dtype<float>() { return "<f4"; }
template <>
std::string npy_dtype<std::uint8_t>() { return "|u1"; }
template <>
std::string npy_dtype<std::uint32_t>() { return "<u4"; }
template <>
std::string npy_dtype<std::int64_t>() { return "<i8"; }

template <class T>
NpyArray NpyArray::of(const std::vector<T>& values, std::vector<std::size_t> shape) {
  NpyArray a;
  a.dtype = npy_dtype<T>();
  a.shape = std::move(shape);
  a.bytes.assign(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  return a;
}

std::size_t NpyArray::element_count() const {
  std::size_t n = 1;
  for (std::size_t s : shape) n *= s;
  return n;
}

template <class T>
std::vector<T> NpyArray::values() const {
  if (dtype != npy_dtype<T>())
    throw FormatError(fmt::format("array has dtype {}, expected {}", printable(dtype), npy_dtype<T>()));
  if (bytes.size() != element_count() * sizeof(T))
    throw FormatError(fmt::format("array holds {} bytes, its shape needs {}", bytes.size(), element_count() * sizeof(T)));
  std::vector<T> v(element_count());
  if (!v.empty()) std::memcpy(v.data(), bytes.data(), bytes.size());  // an empty vector's data() may be null
  return v;
}

template NpyArray NpyArray::of(const std::vector<double>&, std::vector<std::size_t>);
template NpyArray NpyArray::of(const std::vector<std::uint8_t>&, std::vector<std::size_t>);
template NpyArray NpyArray::of(const std::vector<std::uint32_t>&, std::vector<std::size_t>);
template NpyArray NpyArray::of(const std::vector<std::int64_t>&, std::vector<std::size_t>);
template std::vector<double> NpyArray::values() const;
template std::vector<std::uint8_t> NpyArray::values() const;
template std::vector<std::uint32_t> NpyArray::values() const;
template std::vector<std::int64_t> NpyArray::values() const;

namespace {

template <class T>
void put(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <class T>
T get(const std::string& in, std::size_t at) {
  if (at + sizeof(T) > in.size()) throw FormatError("truncated zip structure");
  T value;
  std::memcpy(&value, in.data() + at, sizeof(T));
  return value;
}

// The .npy header of an array: magic, version, length, and the dict padded so that the data starts
// at a multiple of 64 bytes (magic 6 + version 2 + length 2 + header).
std::string npy_header(const std::string& dtype, const std::vector<std::size_t>& dims) {
  std::string shape;
  for (std::size_t s : dims) shape += fmt::format("{}, ", s);
  if (dims.size() > 1) shape.resize(shape.size() - 2);
  else if (dims.size() == 1) shape.resize(shape.size() - 1);
  std::string header = fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': ({}), }}", dtype, shape);
  const std::size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header += '\n';
  std::string out = "\x93NUMPY";
  out += '\x01';
  out += '\x00';
  put<std::uint16_t>(out, static_cast<std::uint16_t>(header.size()));
  out += header;
  return out;
}

NpyArray parse_npy(const std::string& b, const std::string& name) {
  if (b.size() < 10 || b.compare(0, 6, "\x93NUMPY") != 0) throw FormatError(fmt::format("{}: not a .npy array", name));
  const int major = static_cast<unsigned char>(b[6]);
  std::size_t header_len = 0, start = 0;
  if (major == 1) {
    header_len = get<std::uint16_t>(b, 8);
    start = 10;
  } else if (major == 2 || major == 3) {
    header_len = get<std::uint32_t>(b, 8);
    start = 12;
  } else {
    throw FormatError(fmt::format("{}: unsupported .npy version {}", name, major));
  }
  if (start + header_len > b.size()) throw FormatError(fmt::format("{}: truncated .npy header", name));
  const std::string header = b.substr(start, header_len);
  // The header is a Python dict literal. Its three keys are found by hand: std::regex backtracking
  // recurses once per character matched, and a long header (40 kB under ASan, 1 MB in a release
  // build) overflowed the stack.
  constexpr auto npos = std::string::npos;
  auto value_of = [&](std::string_view key) {  // where the value after `key` starts, or npos
    std::size_t at = header.find(key);
    if (at == npos) return npos;
    at += key.size();
    while (at < header.size() && std::isspace(static_cast<unsigned char>(header[at]))) ++at;
    return at;
  };
  NpyArray a;
  const std::size_t descr = value_of("'descr':");
  const std::size_t descr_end =
      descr < header.size() && header[descr] == '\'' ? header.find('\'', descr + 1) : npos;
  if (descr_end == npos || descr_end == descr + 1)
    throw FormatError(fmt::format("{}: .npy header has no descr", name));
  a.dtype = header.substr(descr + 1, descr_end - descr - 1);
  const std::size_t fortran = value_of("'fortran_order':");
  if (fortran == npos || header.compare(fortran, 5, "False") != 0)
    throw FormatError(fmt::format("{}: expected a C-order array", name));
  const std::size_t shape = value_of("'shape':");
  const std::size_t shape_end = shape < header.size() && header[shape] == '(' ? header.find(')', shape + 1) : npos;
  if (shape_end == npos) throw FormatError(fmt::format("{}: .npy header has no shape", name));
  const std::string dims = header.substr(shape + 1, shape_end - shape - 1);
  std::size_t count = 1;
  for (std::size_t first = 0; first < dims.size();) {
    if (!std::isdigit(static_cast<unsigned char>(dims[first]))) {
      ++first;
      continue;
    }
    std::size_t last = first;
    while (last < dims.size() && std::isdigit(static_cast<unsigned char>(dims[last]))) ++last;
    const std::string digits = dims.substr(first, last - first);
    first = last;
    std::size_t dim = 0;
    const auto [end, err] = std::from_chars(digits.data(), digits.data() + digits.size(), dim);
    // Each dimension, and the element count, must fit comfortably in memory arithmetic.
    if (err != std::errc() || end != digits.data() + digits.size() || (dim != 0 && count > (std::size_t{1} << 48) / dim))
      throw FormatError(fmt::format("{}: .npy shape ({}) is too large", name, printable(dims)));
    count *= dim;
    a.shape.push_back(dim);
  }
  a.bytes = b.substr(start + header_len);
  return a;
}

// MS-DOS date/time of 1980-01-01 00:00: fixed, so identical runs give identical files.
constexpr std::uint16_t dos_time = 0;
constexpr std::uint16_t dos_date = (1 << 5) | 1;

}  // namespace

void write_npz(const std::vector<std::pair<std::string, NpyView>>& arrays, const ByteSink& out) {
  std::string directory;
  std::uint64_t written = 0;
  auto emit = [&](std::string_view bytes) {
    out(bytes);
    written += bytes.size();
  };
  for (const auto& [name, array] : arrays) {
    const std::string file = name + ".npy";
    const std::string header = npy_header(array.dtype, array.shape);
    const std::uint64_t data_size = header.size() + array.bytes.size();
    if (written > 0xFFFFFFFFu || data_size > 0xFFFFFFFFu)
      throw FormatError("npz entry larger than 4 GiB (zip64 is not supported)");
    const std::uint32_t crc = crc32_of(crc32_of(0, header), array.bytes);
    const auto offset = static_cast<std::uint32_t>(written);
    const auto size = static_cast<std::uint32_t>(data_size);
    std::string local;
    put<std::uint32_t>(local, 0x04034b50);
    put<std::uint16_t>(local, 20);  // version needed
    put<std::uint16_t>(local, 0);   // flags
    put<std::uint16_t>(local, 0);   // stored
    put<std::uint16_t>(local, dos_time);
    put<std::uint16_t>(local, dos_date);
    put<std::uint32_t>(local, crc);
    put<std::uint32_t>(local, size);
    put<std::uint32_t>(local, size);
    put<std::uint16_t>(local, static_cast<std::uint16_t>(file.size()));
    put<std::uint16_t>(local, 0);
    local += file;
    local += header;
    emit(local);
    emit(array.bytes);

    put<std::uint32_t>(directory, 0x02014b50);
    put<std::uint16_t>(directory, 20);  // made by
    put<std::uint16_t>(directory, 20);  // needed
    put<std::uint16_t>(directory, 0);
    put<std::uint16_t>(directory, 0);
    put<std::uint16_t>(directory, dos_time);
    put<std::uint16_t>(directory, dos_date);
    put<std::uint32_t>(directory, crc);
    put<std::uint32_t>(directory, size);
    put<std::uint32_t>(directory, size);
    put<std::uint16_t>(directory, static_cast<std::uint16_t>(file.size()));
    put<std::uint16_t>(directory, 0);  // extra
    put<std::uint16_t>(directory, 0);  // comment
    put<std::uint16_t>(directory, 0);  // disk
    put<std::uint16_t>(directory, 0);  // internal attributes
    put<std::uint32_t>(directory, 0);  // external attributes
    put<std::uint32_t>(directory, offset);
    directory += file;
  }
  if (written > 0xFFFFFFFFu) throw FormatError("npz file larger than 4 GiB (zip64 is not supported)");
  const auto directory_offset = static_cast<std::uint32_t>(written);
  std::string end = directory;
  put<std::uint32_t>(end, 0x06054b50);
  put<std::uint16_t>(end, 0);
  put<std::uint16_t>(end, 0);
  put<std::uint16_t>(end, static_cast<std::uint16_t>(arrays.size()));
  put<std::uint16_t>(end, static_cast<std::uint16_t>(arrays.size()));
  put<std::uint32_t>(end, static_cast<std::uint32_t>(directory.size()));
  put<std::uint32_t>(end, directory_offset);
  put<std::uint16_t>(end, 0);
  emit(end);
}

std::string make_npz(const std::vector<std::pair<std::string, NpyArray>>& arrays) {
  std::vector<std::pair<std::string, NpyView>> views;
  for (const auto& [name, array] : arrays) views.push_back({name, NpyView{array.dtype, array.shape, array.bytes}});
  std::string out;
  write_npz(views, [&](std::string_view bytes) { out += bytes; });
  return out;
}

std::map<std::string, NpyArray> parse_npz(const std::string& bytes) {
  if (bytes.size() < 22) throw FormatError("too short to be an .npz (zip) file");
  // The end-of-central-directory record is last (we write no archive comment; allow a short one).
  std::size_t eocd = std::string::npos;
  for (std::size_t at = bytes.size() - 22;; --at) {
    if (get<std::uint32_t>(bytes, at) == 0x06054b50) {
      eocd = at;
      break;
    }
    if (at == 0 || bytes.size() - at > 22 + 0xFFFF) break;
  }
  if (eocd == std::string::npos) throw FormatError("not a zip archive (no end-of-central-directory record)");
  const std::size_t entries = get<std::uint16_t>(bytes, eocd + 10);
  std::size_t at = get<std::uint32_t>(bytes, eocd + 16);
  std::map<std::string, NpyArray> arrays;
  for (std::size_t e = 0; e < entries; ++e) {
    if (get<std::uint32_t>(bytes, at) != 0x02014b50) throw FormatError("corrupt zip central directory");
    const std::uint16_t method = get<std::uint16_t>(bytes, at + 10);
    const std::uint32_t crc = get<std::uint32_t>(bytes, at + 16);
    const std::uint32_t csize = get<std::uint32_t>(bytes, at + 20);
    const std::uint32_t usize = get<std::uint32_t>(bytes, at + 24);
    const std::uint16_t name_len = get<std::uint16_t>(bytes, at + 28);
    const std::uint16_t extra_len = get<std::uint16_t>(bytes, at + 30);
    const std::uint16_t comment_len = get<std::uint16_t>(bytes, at + 32);
    const std::uint32_t local = get<std::uint32_t>(bytes, at + 42);
    if (at + 46 + name_len > bytes.size()) throw FormatError("truncated zip central directory");
    const std::string entry = bytes.substr(at + 46, name_len);
    const std::string name = printable(entry);  // as messages show it
    at += 46 + name_len + extra_len + comment_len;
    if (method != 0 || csize != usize)
      throw FormatError(fmt::format("{}: compressed zip entries are not supported (sluice writes stored entries)", name));
    if (get<std::uint32_t>(bytes, local) != 0x04034b50) throw FormatError(fmt::format("{}: corrupt local header", name));
    const std::size_t data_at = local + 30 + get<std::uint16_t>(bytes, local + 26) + get<std::uint16_t>(bytes, local + 28);
    if (data_at + usize > bytes.size()) throw FormatError(fmt::format("{}: truncated data", name));
    const std::string data = bytes.substr(data_at, usize);
    const std::uint32_t actual = crc32_of(0, data);
    if (actual != crc) throw FormatError(fmt::format("{}: checksum mismatch (file damaged)", name));
    std::string key = entry;
    if (key.size() > 4 && key.ends_with(".npy")) key.resize(key.size() - 4);
    NpyArray array = parse_npy(data, name);
    const std::string& dt = array.dtype;
    if (dt.size() != 3 || std::string("<|>").find(dt[0]) == std::string::npos || dt[2] < '1' || dt[2] > '8')
      throw FormatError(fmt::format("{}: unsupported dtype '{}'", name, printable(dt)));
    if (array.bytes.size() != array.element_count() * static_cast<std::size_t>(dt[2] - '0'))
      throw FormatError(fmt::format("{}: data size does not match its shape", name));
    arrays.emplace(key, std::move(array));
  }
  return arrays;
}

}  // namespace sluice
