#include "sluice/io/checkpoint.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <cmath>
#include <cstring>

#include "sluice/case/params.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/npz.hpp"

namespace sluice {

namespace {

constexpr char magic[8] = {'S', 'L', 'U', 'I', 'C', 'E', 'C', 'K'};

template <class T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <class T>
void put_array(std::string& out, const std::vector<T>& v) {
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

class Reader {
 public:
  Reader(const std::string& bytes, std::size_t end, std::string source)
      : bytes_(bytes), end_(end), source_(std::move(source)) {}

  template <class T>
  T get() {
    T value;
    take(&value, sizeof(T));
    return value;
  }
  template <class T>
  void get_array(std::vector<T>& v, std::size_t n) {
    if (n > (end_ - at_) / sizeof(T)) fail("truncated particle data");
    v.resize(n);
    take(v.data(), n * sizeof(T));
  }
  std::string get_string(std::size_t n) {
    if (n > end_ - at_) fail("truncated case text");
    std::string s = bytes_.substr(at_, n);
    at_ += n;
    return s;
  }
  [[nodiscard]] std::size_t remaining() const { return end_ - at_; }
  [[noreturn]] void fail(const std::string& what) const {
    throw FormatError(fmt::format("{}: not a usable checkpoint: {}", source_, what));
  }

 private:
  void take(void* out, std::size_t n) {
    if (n > end_ - at_) fail("truncated");
    if (n == 0) return;  // out is null for an empty array, and memcpy's pointers must not be, even for 0 bytes
    std::memcpy(out, bytes_.data() + at_, n);
    at_ += n;
  }
  const std::string& bytes_;
  std::size_t at_ = 0;
  std::size_t end_;
  std::string source_;
};

}  // namespace

std::string checkpoint_bytes(const Simulation& sim, double wall_seconds) {
  const Particles<2>& p = sim.particles();
  std::string out(magic, sizeof magic);
  put<std::uint32_t>(out, checkpoint_format_version);
  put<std::uint32_t>(out, 2);  // dimension
  const std::string case_text = case_template(sim.config());
  put<std::uint64_t>(out, case_text.size());
  out += case_text;
  const Clock& c = sim.clock();
  put(out, c.time);
  put(out, c.step);
  put(out, c.last_dt);
  put(out, c.leaks);
  put(out, wall_seconds);
  put<std::uint64_t>(out, p.size());
  for (int d = 0; d < 2; ++d) put_array(out, p.position[d]);
  for (int d = 0; d < 2; ++d) put_array(out, p.velocity[d]);
  put_array(out, p.density);
  put_array(out, p.kind);
  put_array(out, p.id);
  put_array(out, p.needs_density_repair);
  const auto crc = static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(out.data()), static_cast<uInt>(out.size())));
  put(out, crc);
  return out;
}

Checkpoint parse_checkpoint(const std::string& bytes, const std::string& source) {
  Reader header(bytes, bytes.size(), source);
  if (bytes.size() < sizeof magic + 12 || std::memcmp(bytes.data(), magic, sizeof magic) != 0)
    header.fail("it does not start with the sluice checkpoint signature");
  std::uint32_t version = 0;
  std::memcpy(&version, bytes.data() + sizeof magic, sizeof version);
  if (version != checkpoint_format_version)
    header.fail(fmt::format("format version {}, this sluice reads version {}", version, checkpoint_format_version));
  std::uint32_t stored_crc = 0;
  std::memcpy(&stored_crc, bytes.data() + bytes.size() - sizeof stored_crc, sizeof stored_crc);
  const auto crc = static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size() - sizeof stored_crc)));
  if (crc != stored_crc) header.fail("checksum mismatch (the file is damaged or incomplete)");

  Reader r(bytes, bytes.size() - sizeof stored_crc, source);
  r.get_string(sizeof magic);
  r.get<std::uint32_t>();
  if (r.get<std::uint32_t>() != 2) r.fail("written by a run of another dimension");
  const auto case_length = r.get<std::uint64_t>();
  const std::string case_text = r.get_string(case_length);
  Checkpoint cp;
  try {
    cp.config = parse_case(case_text, source + " (stored case)");
  } catch (const CaseError& e) {
    r.fail(e.what());
  }
  cp.clock.time = r.get<double>();
  cp.clock.step = r.get<std::int64_t>();
  cp.clock.last_dt = r.get<double>();
  cp.clock.leaks = r.get<std::int64_t>();
  cp.wall_seconds = r.get<double>();
  // A run's clock starts at zero and only moves forward. A negative or non-finite time (possible only in
  // a crafted file, the CRC passing) made a restart step forever from t = -1e300 or run to "t = nan".
  auto usable = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (!usable(cp.clock.time) || !usable(cp.clock.last_dt) || !usable(cp.wall_seconds) || cp.clock.step < 0 ||
      cp.clock.leaks < 0)
    r.fail(fmt::format("impossible clock (time {}, step {}, last dt {}, leaks {}, wall time {})", cp.clock.time,
                       cp.clock.step, cp.clock.last_dt, cp.clock.leaks, cp.wall_seconds));
  const auto n = r.get<std::uint64_t>();
  // 8 doubles' worth of bytes per particle at most; reject absurd counts before allocating.
  if (n > r.remaining() / 40) r.fail("particle count does not match the file size");
  Particles<2>& p = cp.particles;
  p.resize(n);
  for (int d = 0; d < 2; ++d) r.get_array(p.position[d], n);
  for (int d = 0; d < 2; ++d) r.get_array(p.velocity[d], n);
  r.get_array(p.density, n);
  r.get_array(p.kind, n);
  r.get_array(p.id, n);
  r.get_array(p.needs_density_repair, n);
  if (r.remaining() != 0) r.fail("trailing bytes after the particle data");
  std::vector<std::uint8_t> seen(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (static_cast<std::uint8_t>(p.kind[i]) > 1) r.fail("unknown particle kind");
    if (p.id[i] >= n || seen[p.id[i]]++) r.fail("particle ids are not a permutation of 0..n-1");
  }
  return cp;
}

void write_checkpoint(const std::filesystem::path& path, const Simulation& sim, double wall_seconds) {
  write_file_atomic(path, checkpoint_bytes(sim, wall_seconds));
}

Checkpoint read_checkpoint(const std::filesystem::path& path) {
  return parse_checkpoint(read_file(path), path.string());
}

}  // namespace sluice
