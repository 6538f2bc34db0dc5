#include "sluice/io/checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <type_traits>

#include "sluice/case/case_error.hpp"
#include "sluice/case/params.hpp"
#include "sluice/case/value_text.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/npz.hpp"

namespace sluice {

namespace {

constexpr char magic[8] = {'S', 'L', 'U', 'I', 'C', 'E', 'C', 'K'};

// Passes bytes on to a sink as they come, with their running checksum: the particles' arrays go to
// the file without a copy of the whole checkpoint in memory.
struct SinkWriter {
  const ByteSink& out;
  std::uint32_t crc = 0;
  void append(const char* data, std::size_t n) {
    crc = crc32_of(crc, std::string_view(data, n));
    out(std::string_view(data, n));
  }
  SinkWriter& operator+=(std::string_view s) {
    append(s.data(), s.size());
    return *this;
  }
};

template <class T, class Out>
void put(Out& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <class T, class Out>
void put_array(Out& out, const std::vector<T>& v) {
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
  // The file cannot be read as a checkpoint (damaged, truncated, another format): exit status 1.
  [[noreturn]] void fail(const std::string& what) const {
    throw FormatError(fmt::format("{}: not a usable checkpoint: {}", source_, what));
  }
  // The file reads, but a value in it is not one a run can hold (possible only in a file made or
  // altered by hand, its checksum passing): refused as bad input, as a case file's value is.
  [[noreturn]] void refuse(const std::string& what) const {
    throw CaseError(fmt::format("{}: not a usable checkpoint: {}", source_, what));
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

// Element type codes of the field table.
template <class T>
constexpr std::uint8_t element_code() {
  static_assert(std::is_same_v<T, double> || sizeof(T) == 1 || std::is_same_v<T, std::uint32_t>);
  if constexpr (std::is_same_v<T, double>) return 1;
  else if constexpr (sizeof(T) == 1) return 2;  // std::uint8_t and Kind
  else return 3;                                // std::uint32_t
}

// A field's element type code and number of components, as the field table records them.
struct FieldLayout {
  std::uint8_t code = 0;
  std::uint8_t components = 0;
};

template <class Field>
FieldLayout layout_of(Field& /*field*/) {
  FieldLayout l;
  using Element = typename std::remove_cvref_t<Field>::value_type;
  if constexpr (std::is_arithmetic_v<Element> || std::is_enum_v<Element>) {
    l.code = element_code<Element>();
    l.components = 1;
  } else {
    l.code = element_code<typename Element::value_type>();
    l.components = static_cast<std::uint8_t>(std::tuple_size_v<std::remove_cvref_t<Field>>);
  }
  return l;
}

// The roles of the fields a checkpoint holds: those marked `checkpoint`, and while the leapfrog
// carries its rates into the next step, those marked `carried`.
unsigned stored_roles(bool rates_carried) {
  return field_role::checkpoint | (rates_carried ? field_role::carried : 0u);
}

template <int Dim, class Out>
void put_particles(Out& out, const Particles<Dim>& p, bool rates_carried) {
  const unsigned roles = stored_roles(rates_carried);
  std::uint32_t fields = 0;
  Particles<Dim>::fields(p, [&](const FieldSpec& info, const auto&) { fields += info.has(roles); });
  put<std::uint32_t>(out, fields);
  Particles<Dim>::fields(p, [&](const FieldSpec& info, const auto& field) {
    if (!info.has(roles)) return;
    put<std::uint16_t>(out, static_cast<std::uint16_t>(info.name.size()));
    out += info.name;
    const FieldLayout layout = layout_of(field);
    put(out, layout.code);
    put(out, layout.components);
    Particles<Dim>::components(field, [&](const auto& c) { put_array(out, c); });
  });
}

template <int Dim>
Particles<Dim> get_particles(Reader& r, std::size_t n, bool rates_carried, std::uint32_t version) {
  Particles<Dim> p;
  p.resize(n);
  const unsigned roles = stored_roles(rates_carried);
  // Versions before 5 have no body field: the solver gives each particle its body from the case, by id.
  const auto in_file = [&](const FieldSpec& info) { return info.has(roles) && (version >= 5 || info.name != "body"); };
  const auto stored = r.get<std::uint32_t>();
  std::uint32_t expected = 0;
  Particles<Dim>::fields(p, [&](const FieldSpec& info, const auto&) { expected += in_file(info); });
  if (stored != expected)
    r.fail(fmt::format("{} particle fields, this sluice writes {}{}", stored, expected,
                       rates_carried ? " with carried rates" : ""));
  // The fields in registry order, each named and typed as this sluice declares it.
  Particles<Dim>::fields(p, [&](const FieldSpec& info, auto& field) {
    if (!in_file(info)) return;
    const auto length = r.get<std::uint16_t>();
    const std::string name = r.get_string(length);
    if (name != info.name) r.fail(fmt::format("field '{}' where '{}' was expected", printable(name), info.name));
    const auto code = r.get<std::uint8_t>();
    const auto components = r.get<std::uint8_t>();
    const FieldLayout want = layout_of(field);
    if (code != want.code || components != want.components)
      r.fail(fmt::format("field '{}' has element type {} and {} components; expected {} and {}", name, code,
                         components, want.code, want.components));
    Particles<Dim>::components(field, [&](auto& c) { r.get_array(c, n); });
  });
  return p;
}

}  // namespace

void write_checkpoint_bytes(const Simulation& sim, double wall_seconds, const ByteSink& sink) {
  std::string head(magic, sizeof magic);
  put<std::uint32_t>(head, checkpoint_format_version);
  put<std::uint32_t>(head, static_cast<std::uint32_t>(sim.dimension()));
  const std::string case_text = case_template(sim.config());
  put<std::uint64_t>(head, case_text.size());
  head += case_text;
  const Clock& c = sim.clock();
  put(head, c.time);
  put(head, c.step);
  put(head, c.last_dt);
  put(head, c.leaks);
  put(head, wall_seconds);
  put<std::uint8_t>(head, c.rates_carried ? 1 : 0);
  if (c.rates_carried) {
    put(head, c.rates.max_acceleration);
    put(head, c.rates.max_relative_speed);
    put(head, c.rates.max_density);
    put(head, c.rates.min_fluid_distance);
  }
  put(head, c.outflow);
  put<std::uint32_t>(head, static_cast<std::uint32_t>(c.absorbers.size()));
  for (double v : c.absorbers) put(head, v);
  put<std::uint32_t>(head, static_cast<std::uint32_t>(c.floating.size()));
  for (double v : c.floating) put(head, v);
  // Every process's particles, on the root (the other processes write nothing).
  sim.visit([&](const auto& solver) {
    solver.with_all_particles([&](const auto& p) {
      SinkWriter out{sink};
      out += head;
      put<std::uint64_t>(out, p.size());
      put_particles(out, p, c.rates_carried);
      const std::uint32_t crc = out.crc;
      sink(std::string_view(reinterpret_cast<const char*>(&crc), sizeof crc));
    });
  });
}

std::string checkpoint_bytes(const Simulation& sim, double wall_seconds) {
  std::string out;
  write_checkpoint_bytes(sim, wall_seconds, [&](std::string_view bytes) { out += bytes; });
  return out;
}

bool checkpoint_checksum_matches(std::string_view bytes) {
  std::uint32_t stored = 0;
  if (bytes.size() < sizeof stored) return false;
  std::memcpy(&stored, bytes.data() + bytes.size() - sizeof stored, sizeof stored);
  return crc32_of(0, bytes.substr(0, bytes.size() - sizeof stored)) == stored;
}

Checkpoint parse_checkpoint(const std::string& bytes, const std::string& source) {
  Reader header(bytes, bytes.size(), source);
  if (bytes.size() < sizeof magic + 12 || std::memcmp(bytes.data(), magic, sizeof magic) != 0)
    header.fail("it does not start with the sluice checkpoint signature");
  std::uint32_t version = 0;
  std::memcpy(&version, bytes.data() + sizeof magic, sizeof version);
  if (version == 1)
    header.fail("format version 1, written by an earlier sluice (before the field table of version 2); run that "
                "sluice to finish the run, or start the case again");
  if (version < 2 || version > checkpoint_format_version)
    header.fail(fmt::format("format version {}, this sluice reads versions 2 to {}", version,
                            checkpoint_format_version));
  if (!checkpoint_checksum_matches(bytes)) header.fail("checksum mismatch (the file is damaged or incomplete)");

  Reader r(bytes, bytes.size() - sizeof(std::uint32_t), source);
  r.get_string(sizeof magic);
  r.get<std::uint32_t>();
  const auto dimension = r.get<std::uint32_t>();
  if (dimension != 2 && dimension != 3) r.fail(fmt::format("dimension {}, expected 2 or 3", dimension));
  const auto case_length = r.get<std::uint64_t>();
  const std::string case_text = r.get_string(case_length);
  Checkpoint cp;
  try {
    cp.config = parse_case(case_text, source + " (stored case)");
  } catch (const CaseError& e) {
    r.fail(e.what());
  }
  if (static_cast<std::uint32_t>(cp.config.dimension) != dimension)
    r.fail(fmt::format("{}D particles with a {}D case", dimension, cp.config.dimension));
  cp.clock.time = r.get<double>();
  cp.clock.step = r.get<std::int64_t>();
  cp.clock.last_dt = r.get<double>();
  cp.clock.leaks = r.get<std::int64_t>();
  cp.wall_seconds = r.get<double>();
  // Version 2 (before the leapfrog) carries no rates.
  if (version >= 3) {
    const auto carried = r.get<std::uint8_t>();
    if (carried > 1) r.refuse(fmt::format("rates-carried flag {}, expected 0 or 1", carried));
    cp.clock.rates_carried = carried == 1;
  }
  if (cp.clock.rates_carried) {
    RateSummary& s = cp.clock.rates;
    s.max_acceleration = r.get<double>();
    s.max_relative_speed = r.get<double>();
    s.max_density = r.get<double>();
    s.min_fluid_distance = r.get<double>();
    auto usable_rate = [](double v) { return std::isfinite(v) && v >= 0.0; };
    if (!usable_rate(s.max_acceleration) || !usable_rate(s.max_relative_speed) || !usable_rate(s.max_density) ||
        !usable_rate(s.min_fluid_distance))
      r.refuse(fmt::format("impossible summary of the carried rates (max acceleration {}, max relative speed {}, max "
                         "density {}, min distance {})",
                         s.max_acceleration, s.max_relative_speed, s.max_density, s.min_fluid_distance));
    if (cp.config.integrator != Integrator::leapfrog)
      r.refuse(fmt::format("rates carried over with the {} integrator (only the leapfrog carries them)",
                         name_of(cp.config.integrator, integrator_names)));
  }
  // Versions 2 and 3 (before outflow) removed no particles.
  if (version >= 4) cp.clock.outflow = r.get<std::int64_t>();
  // Version 6 keeps the absorbing pistons' states (before it there were none).
  if (version >= 6) {
    const auto n = r.get<std::uint32_t>();
    if (n > 5 * 255) r.refuse(fmt::format("{} values of absorbing pistons' state, more than 255 walls hold", n));
    for (std::uint32_t k = 0; k < n; ++k) {
      const double v = r.get<double>();
      if (!std::isfinite(v)) r.refuse(fmt::format("an absorbing piston's state value {} is not a finite number", v));
      cp.clock.absorbers.push_back(v);
    }
  }
  // Version 7 keeps the floating bodies' states (before it there were none).
  if (version >= 7) {
    const auto n = r.get<std::uint32_t>();
    if (n > FloatingState::packed_size * 255) r.refuse(fmt::format("{} values of floating bodies' state, more than 255 walls hold", n));
    for (std::uint32_t k = 0; k < n; ++k) {
      const double v = r.get<double>();
      if (!std::isfinite(v)) r.refuse(fmt::format("a floating body's state value {} is not a finite number", v));
      cp.clock.floating.push_back(v);
    }
  }
  // A run's clock starts at zero and only moves forward. A negative or non-finite time (possible only in
  // a crafted file, the CRC passing) made a restart step forever from t = -1e300 or run to "t = nan".
  // Counts stay far below the largest 64-bit integer, so that adding a run's steps and leaks to them
  // cannot overflow (a crafted INT64_MAX turned negative in the summary).
  auto usable = [](double v) { return std::isfinite(v) && v >= 0.0; };
  auto countable = [](std::int64_t k) { return k >= 0 && k <= kLargestCount; };
  if (!usable(cp.clock.time) || !usable(cp.clock.last_dt) || !usable(cp.wall_seconds) || !countable(cp.clock.step) ||
      !countable(cp.clock.leaks) || !countable(cp.clock.outflow))
    r.refuse(fmt::format("impossible clock (time {}, step {}, last dt {}, leaks {}, outflow {}, wall time {})",
                       cp.clock.time, cp.clock.step, cp.clock.last_dt, cp.clock.leaks, cp.clock.outflow,
                       cp.wall_seconds));
  const auto n = r.get<std::uint64_t>();
  // 8 doubles' worth of bytes per particle at most; reject absurd counts before allocating.
  if (n > r.remaining() / 40) r.fail("particle count does not match the file size");
  // The ids: distinct, below the particle count at the start (this count and those removed as outflow).
  if (static_cast<std::uint64_t>(cp.clock.outflow) > std::numeric_limits<std::uint32_t>::max())
    r.refuse(fmt::format("outflow {} is more particles than a run can hold", cp.clock.outflow));
  const std::size_t ids = n + static_cast<std::size_t>(cp.clock.outflow);
  const auto check = [&](const auto& p) {
    if (r.remaining() != 0) r.fail("trailing bytes after the particle data");
    for (std::size_t i = 0; i < n; ++i) {
      if (static_cast<std::uint8_t>(p.kind[i]) > 1)
        r.refuse(fmt::format("unknown particle kind {} (id {})", static_cast<int>(p.kind[i]), p.id[i]));
      if (p.needs_density_repair[i] > 1)
        r.refuse(fmt::format("density-repair flag {} (id {}), expected 0 or 1", p.needs_density_repair[i], p.id[i]));
      if (!(p.density[i] > 0.0) || !std::isfinite(p.density[i]))
        r.refuse(fmt::format("density {} (id {}), expected a positive finite number", p.density[i], p.id[i]));
    }
    // Every stored number finite: a NaN position or velocity would run as far as the first step.
    using P = std::remove_cvref_t<decltype(p)>;
    P::fields(p, [&](const FieldSpec& info, const auto& field) {
      using Element = typename std::remove_cvref_t<decltype(field)>::value_type;
      if (!info.has(stored_roles(cp.clock.rates_carried))) return;
      if constexpr (std::is_floating_point_v<Element>) {
        for (std::size_t i = 0; i < n; ++i)
          if (!std::isfinite(field[i]))
            r.refuse(fmt::format("{} {} (id {}), expected a finite number", info.name, field[i], p.id[i]));
      } else if constexpr (!std::is_arithmetic_v<Element> && !std::is_enum_v<Element>) {
        for (std::size_t d = 0; d < field.size(); ++d)
          for (std::size_t i = 0; i < n; ++i)
            if (!std::isfinite(field[d][i]))
              r.refuse(fmt::format("{} component {} is {} (id {}), expected a finite number", info.name, "xyz"[d],
                                   field[d][i], p.id[i]));
      }
    });
    // Sorted rather than marked in a table of `ids` entries: a crafted outflow must not make the
    // check allocate gigabytes.
    std::vector<std::uint32_t> sorted = p.id;
    std::sort(sorted.begin(), sorted.end());
    const bool distinct = std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
    if (!distinct || (n > 0 && sorted.back() >= ids))
      r.refuse(cp.clock.outflow == 0 ? std::string("particle ids are not a permutation of 0..n-1")
                                   : fmt::format("particle ids are not distinct ids below {} (the {} particles and "
                                                 "the {} removed as outflow)",
                                                 ids, n, cp.clock.outflow));
  };
  if (dimension == 3) {
    Particles<3> p = get_particles<3>(r, n, cp.clock.rates_carried, version);
    check(p);
    cp.particles = std::move(p);
  } else {
    Particles<2> p = get_particles<2>(r, n, cp.clock.rates_carried, version);
    check(p);
    cp.particles = std::move(p);
  }
  return cp;
}

void write_checkpoint(const std::filesystem::path& path, const Simulation& sim, double wall_seconds) {
  std::optional<AtomicFile> file;
  if (sim.is_root()) file.emplace(path);
  write_checkpoint_bytes(sim, wall_seconds, [&](std::string_view bytes) { file->write(bytes); });  // collective
  if (file) file->commit();
}

Checkpoint read_checkpoint(const std::filesystem::path& path) {
  return parse_checkpoint(read_file(path), path.string());
}

}  // namespace sluice
