// What each fuzz target does with one input, shared with tests/test_fuzz_regressions.cpp so that a
// kept input is replayed through exactly the code the fuzzer ran.
//
// The contract checked: a parser either returns or throws its documented error type (CaseError for
// case files, FormatError for checkpoints and frames, and CaseError for a checkpoint that reads but
// holds a value no run can hold; MeshError for meshes). Any other exception, a crash, a sanitizer
// report, or an accepted input that breaks one of the properties below is a bug.
#pragma once

#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "sluice/case/params.hpp"
#include "sluice/geometry/mesh_file.hpp"
#include "sluice/geometry/mesh_solid.hpp"
#include "sluice/geometry/triangle_mesh.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/frames.hpp"
#include "sluice/io/npz.hpp"

namespace sluice::fuzz {

// An accepted input that breaks a property (not an error the parser reports): a bug, like a crash.
struct PropertyViolation : std::logic_error {
  using std::logic_error::logic_error;
};

enum class Outcome { accepted, rejected };

inline void require(bool ok, const std::string& what) {
  if (!ok) throw PropertyViolation(what);
}

// Case files: TOML text -> a validated Case, or CaseError. An accepted case must survive the
// template round trip (`sluice init` writes the template and checkpoints store the case as it:
// a case that does not read back cannot be restarted).
inline Outcome check_case(const std::string& text) {
  Case c;
  try {
    c = parse_case(text, "fuzz.toml");
  } catch (const CaseError&) {
    return Outcome::rejected;
  }
  const std::string once = case_template(c);
  Case again;
  try {
    again = parse_case(once, "template");
  } catch (const CaseError& e) {
    throw PropertyViolation(std::string("the template of an accepted case is refused: ") + e.what());
  }
  require(case_template(again) == once, "the case template does not read back unchanged");
  return Outcome::accepted;
}

// Checkpoints end with a CRC-32 of everything before it. The bytes with that checksum made to
// match, so that the fuzzer reaches the parsing behind the check, not only the check.
inline std::string with_checkpoint_crc_fixed(std::string bytes) {
  if (bytes.size() < 4) return bytes;
  const auto crc = static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size() - 4)));
  std::memcpy(bytes.data() + bytes.size() - 4, &crc, 4);
  return bytes;
}

// Past the reading, what `sluice run --restart` does with an accepted checkpoint: the solver built
// from it (which checks the particles against the set-up of the stored case), the instability guard
// on the state it starts from (io/run.cpp, check_start) and, for a state that passes, two steps. Only
// for a stored case whose set-up is small (the fuzzer's inputs must stay fast; a large one builds the
// same way). A step may find the state unstable (std::runtime_error, as a run reports it); anything
// else thrown, a crash or a sanitizer report is a bug.
inline Outcome check_restart(Checkpoint& cp) {
  double lattice_points = 1.0;
  const Vec3 tank = cp.config.tank_size();
  for (int d = 0; d < cp.config.dimension; ++d)
    lattice_points *= (tank[d] + 4 * cp.config.smoothing_length()) / cp.config.dx;
  if (lattice_points > 2e4) return Outcome::accepted;
  try {
    Simulation sim(cp.config, std::move(cp.particles), cp.clock, 1);
    if (!sim.check_health().ok()) return Outcome::rejected;
    try {
      sim.step();
      sim.step();
    } catch (const std::runtime_error&) {
    }
  } catch (const CaseError&) {
    return Outcome::rejected;
  }
  return Outcome::accepted;
}

inline Outcome check_checkpoint_bytes(const std::string& bytes) {
  Checkpoint cp;
  try {
    cp = parse_checkpoint(bytes, "fuzz.bin");
  } catch (const FormatError&) {
    return Outcome::rejected;
  } catch (const CaseError&) {  // a value no run can hold (Reader::refuse)
    return Outcome::rejected;
  }
  // A restart continues from the clock: a negative or non-finite one made it step forever.
  auto usable = [](double v) { return std::isfinite(v) && v >= 0.0; };
  require(usable(cp.clock.time) && usable(cp.clock.last_dt) && usable(cp.wall_seconds) && cp.clock.step >= 0 &&
              cp.clock.leaks >= 0,
          "an accepted checkpoint has an impossible clock");
  // The leapfrog's carried rates choose the next time step.
  const RateSummary& r = cp.clock.rates;
  require(!cp.clock.rates_carried || (usable(r.max_acceleration) && usable(r.max_relative_speed) &&
                                      usable(r.max_density) && usable(r.min_fluid_distance)),
          "an accepted checkpoint has an impossible summary of carried rates");
  std::visit(
      [&](const auto& p) {
        const std::size_t n = p.size();
        bool same_lengths = p.kind.size() == n && p.id.size() == n && p.needs_density_repair.size() == n;
        for (const auto& component : p.position) same_lengths = same_lengths && component.size() == n;
        for (const auto& component : p.velocity) same_lengths = same_lengths && component.size() == n;
        for (const auto& component : p.acceleration) same_lengths = same_lengths && component.size() == n;
        same_lengths = same_lengths && p.density_rate.size() == n;
        require(same_lengths, "an accepted checkpoint has particle arrays of different lengths");
        std::vector<bool> seen(n, false);
        for (std::size_t i = 0; i < n; ++i) {
          require(static_cast<std::uint8_t>(p.kind[i]) <= 1, "an accepted checkpoint has an unknown particle kind");
          require(p.id[i] < n && !seen[p.id[i]], "an accepted checkpoint's ids are not a permutation");
          seen[p.id[i]] = true;
        }
      },
      cp.particles);
  return check_restart(cp);
}

// Checkpoint bytes, as given and with their checksum fixed.
inline Outcome check_checkpoint(const std::string& bytes) {
  const Outcome as_given = check_checkpoint_bytes(bytes);
  const Outcome fixed = check_checkpoint_bytes(with_checkpoint_crc_fixed(bytes));
  return as_given == Outcome::accepted ? as_given : fixed;
}

// .npz archives carry a CRC-32 per entry in the zip central directory. The bytes with every CRC
// that can be located made to match its entry's data (all reads bounds-checked; anything that does
// not look like a zip is returned unchanged).
inline std::string with_npz_crcs_fixed(std::string b) {
  auto u16 = [&](std::size_t at) -> std::uint64_t {
    std::uint16_t v = 0;
    if (at <= b.size() && b.size() - at >= 2) std::memcpy(&v, b.data() + at, 2);
    return v;
  };
  auto u32 = [&](std::size_t at) -> std::uint64_t {
    std::uint32_t v = 0;
    if (at <= b.size() && b.size() - at >= 4) std::memcpy(&v, b.data() + at, 4);
    return v;
  };
  if (b.size() < 22) return b;
  std::size_t eocd = std::string::npos;
  for (std::size_t at = b.size() - 22;; --at) {
    if (u32(at) == 0x06054b50) {
      eocd = at;
      break;
    }
    if (at == 0 || b.size() - at > 22 + 0xFFFF) break;
  }
  if (eocd == std::string::npos) return b;
  const std::uint64_t entries = u16(eocd + 10);
  std::uint64_t at = u32(eocd + 16);
  for (std::uint64_t e = 0; e < entries && at + 46 <= b.size(); ++e) {
    if (u32(at) != 0x02014b50) break;
    const std::uint64_t size = u32(at + 24);
    const std::uint64_t local = u32(at + 42);
    const std::uint64_t data_at = local + 30 + u16(local + 26) + u16(local + 28);
    if (data_at <= b.size() && b.size() - data_at >= size) {
      const auto crc = static_cast<std::uint32_t>(
          crc32(0L, reinterpret_cast<const Bytef*>(b.data() + data_at), static_cast<uInt>(size)));
      std::memcpy(b.data() + at + 16, &crc, 4);
    }
    at += 46 + u16(at + 28) + u16(at + 30) + u16(at + 32);
  }
  return b;
}

inline bool same_bits(const void* a, const void* b, std::size_t n) { return n == 0 || std::memcmp(a, b, n) == 0; }

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && same_bits(a.data(), b.data(), a.size() * sizeof(T));
}

inline bool same_bits(const FrameField& a, const FrameField& b) {
  if (a.short_name != b.short_name || a.values.index() != b.values.index()) return false;
  return std::visit(
      [&](const auto& values) { return same_bits(values, std::get<std::decay_t<decltype(values)>>(b.values)); },
      a.values);
}

inline Outcome check_frame_bytes(const std::string& bytes) {
  Frame f;
  try {
    f = frame_from_npz(bytes, "fuzz.npz");
  } catch (const FormatError&) {
    return Outcome::rejected;
  }
  const std::size_t n = f.size();
  for (const FrameField& field : f.fields)
    require(field.element_count() == (field.vector ? static_cast<std::size_t>(f.dimension) : 1) * n,
            "an accepted frame has arrays of inconsistent lengths");
  // What was read is written back and read again unchanged, bit for bit (NaNs included).
  Frame g;
  try {
    g = frame_from_npz(frame_to_npz(f), "rewritten.npz");
  } catch (const FormatError& e) {
    throw PropertyViolation(std::string("an accepted frame, written back, is refused: ") + e.what());
  }
  bool same = same_bits(&f.time, &g.time, sizeof f.time) && f.step == g.step && same_bits(&f.dx, &g.dx, sizeof f.dx) &&
              f.dimension == g.dimension && f.fields.size() == g.fields.size();
  for (std::size_t k = 0; same && k < f.fields.size(); ++k) same = same_bits(f.fields[k], g.fields[k]);
  require(same, "an accepted frame does not read back unchanged after writing it");
  return Outcome::accepted;
}

// Frame bytes, as given and with their zip checksums fixed.
inline Outcome check_frame(const std::string& bytes) {
  const Outcome as_given = check_frame_bytes(bytes);
  const Outcome fixed = check_frame_bytes(with_npz_crcs_fixed(bytes));
  return as_given == Outcome::accepted ? as_given : fixed;
}

// Meshes: bytes -> a closed triangle mesh, or MeshError, read both as STL (ASCII or binary) and as
// OBJ. An accepted closed mesh is made into a solid and asked the queries the set-up asks (inside,
// distance, closest point) at its corners and centre, which must answer with numbers.
inline Outcome check_mesh_as(const std::string& bytes, const std::string& name) {
  TriangleMesh mesh;
  try {
    mesh = read_mesh(bytes, name);
    check_closed_mesh(mesh);
  } catch (const MeshError&) {
    return Outcome::rejected;
  }
  for (const Vec<3>& v : mesh.vertices)
    require(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]),
            "an accepted mesh has a vertex that is not finite");
  const MeshSolid solid(mesh);
  const Vec<3> lo = solid.lower(), hi = solid.upper();
  const Vec<3> centre{0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  for (const Vec<3>& x : {lo, hi, centre}) {
    (void)solid.contains(x);
    require(std::isfinite(solid.signed_distance(x)), "a distance to an accepted mesh is not finite");
    const SurfacePoint<3> s = solid.closest_surface_point(x);
    require(std::isfinite(s.point[0]) && std::isfinite(s.point[1]) && std::isfinite(s.point[2]),
            "a closest point of an accepted mesh is not finite");
  }
  return Outcome::accepted;
}

inline Outcome check_mesh(const std::string& bytes) {
  const Outcome stl = check_mesh_as(bytes, "fuzz.stl");
  const Outcome obj = check_mesh_as(bytes, "fuzz.obj");
  return stl == Outcome::accepted ? stl : obj;
}

}  // namespace sluice::fuzz
