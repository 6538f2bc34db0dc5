// The file formats and the writers: NumPy .npz and frames, checkpoints (version and checksum), the
// ParaView collection, atomic files and their temporary files, files that grow by appended records,
// and clear errors for damaged input and unwritable output.
// Our files are also read back by real numpy and meshio in the Python tests (test_outputs.py).
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "sluice/case/case_template.hpp"
#include "sluice/case/params.hpp"
#include "sluice/io/append_file.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/frames.hpp"
#include "sluice/io/npz.hpp"
#include "sluice/io/probes.hpp"
#include "sluice/io/run.hpp"
#include "sluice/simulation.hpp"

using namespace sluice;
namespace fs = std::filesystem;

namespace {

// A fresh, empty directory for one test, removed at the end.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            fmt::format("sluice_test_io_{}_{}_{}", info->test_suite_name(), info->name(), ::getpid());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

Frame small_frame() {
  Frame f;
  f.time = 0.30000000000000004;
  f.step = 1234;
  f.dx = 0.025;
  f.position() = {0.0, 0.5, 1.0, 1.5, -2.0, 2.5};
  f.velocity() = {0.1, -0.2, 0.3, -0.4, 1e-300, -0.0};
  f.density() = {1000.0, 1001.5, 999.25};
  f.pressure() = {0.0, 12.5, -3.75};
  f.kind() = {0, 0, 1};
  f.id() = {0, 1, 2};
  f.body() = {0, 0, 1};
  return f;
}

Case tiny_case(double dx = 0.1) {
  return parse_case(fmt::format(R"(
[case]
name = "tiny"
description = "a small tank for the I/O tests"
[domain]
dx = {}
)", dx) + R"(
[tank]
width = 1.0
height = 1.0
[time]
end = 1.0
[[water]]
min = [0.0, 0.0]
max = [0.4, 0.6]
[[probe]]
name = "p_bottom"
type = "pressure"
point = [0.2, 0.1]
)",
                    "I/O test case");
}

// The bytes with their trailing CRC-32 recomputed, so that a change reaches the parser behind it.
std::string with_crc_fixed(std::string bytes) {
  const auto crc = static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size() - 4)));
  std::memcpy(bytes.data() + bytes.size() - 4, &crc, 4);
  return bytes;
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(Npz, RoundTripKeepsNamesShapesDtypesAndValues) {
  const std::vector<double> d = {1.5, -2.25, 3e-300, 4e300, 0.0, -0.0};
  const std::vector<std::uint8_t> u8 = {0, 1, 255};
  const std::vector<std::uint32_t> u32 = {0, 7, 4294967295u};
  const std::vector<std::int64_t> i64 = {-9000000000000000000LL};
  const std::string bytes = make_npz({
      {"matrix", NpyArray::of(d, {3, 2})},
      {"bytes", NpyArray::of(u8, {3})},
      {"ids", NpyArray::of(u32, {3})},
      {"scalar", NpyArray::of(i64, {})},
  });
  const auto arrays = parse_npz(bytes);
  ASSERT_EQ(arrays.size(), 4u);
  EXPECT_EQ(arrays.at("matrix").dtype, "<f8");
  EXPECT_EQ(arrays.at("matrix").shape, (std::vector<std::size_t>{3, 2}));
  EXPECT_EQ(arrays.at("matrix").values<double>(), d);
  EXPECT_EQ(arrays.at("bytes").dtype, "|u1");
  EXPECT_EQ(arrays.at("bytes").values<std::uint8_t>(), u8);
  EXPECT_EQ(arrays.at("ids").dtype, "<u4");
  EXPECT_EQ(arrays.at("ids").values<std::uint32_t>(), u32);
  EXPECT_TRUE(arrays.at("scalar").shape.empty());
  EXPECT_EQ(arrays.at("scalar").values<std::int64_t>(), i64);
  // Asking for the wrong type is an error, not a reinterpretation.
  EXPECT_THROW((void)arrays.at("ids").values<double>(), FormatError);
}

// The names and dtypes of an archive's arrays are the file's text: messages show them escaped.
TEST(Npz, NamesAndDtypesFromTheFileAreShownEscaped) {
  NpyArray short_data = NpyArray::of(std::vector<double>{1.0}, {1});
  short_data.bytes.pop_back();
  const std::string message = error_of([&] { parse_npz(make_npz({{"x\x1b]0;title\x07", short_data}})); });
  EXPECT_NE(message.find(R"(x\u001B]0;title\u0007.npy: data size does not match its shape)"), std::string::npos) << message;
  NpyArray odd_dtype = NpyArray::of(std::vector<double>{1.0}, {1});
  odd_dtype.dtype = "<\x1b" "8";
  const auto arrays = parse_npz(make_npz({{"x", odd_dtype}}));
  const std::string dtype = error_of([&] { (void)arrays.at("x").values<double>(); });
  EXPECT_NE(dtype.find(R"(array has dtype <\u001B8, expected <f8)"), std::string::npos) << dtype;
}

TEST(Npz, NpyHeadersArePaddedSoDataIsAligned) {
  // NEP 1: the header (magic through newline) is padded to a multiple of 64 bytes.
  const std::string bytes = make_npz({{"a", NpyArray::of(std::vector<double>{1.0, 2.0}, {2})}});
  const auto magic = bytes.find("\x93NUMPY");
  ASSERT_NE(magic, std::string::npos);
  std::uint16_t header_len = 0;
  std::memcpy(&header_len, bytes.data() + magic + 8, 2);
  EXPECT_EQ((10 + header_len) % 64, 0);
  EXPECT_EQ(bytes[magic + 10 + header_len - 1], '\n');
  EXPECT_NE(bytes.find("'shape': (2,)"), std::string::npos);
}

TEST(Frames, NpzRoundTrip) {
  const Frame f = small_frame();
  const Frame g = frame_from_npz(frame_to_npz(f), "memory");
  EXPECT_EQ(g.time, f.time);
  EXPECT_EQ(g.step, f.step);
  EXPECT_EQ(g.dx, f.dx);
  EXPECT_EQ(g.position(), f.position());
  EXPECT_EQ(g.velocity(), f.velocity());
  EXPECT_EQ(g.density(), f.density());
  EXPECT_EQ(g.pressure(), f.pressure());
  EXPECT_EQ(g.kind(), f.kind());
  EXPECT_EQ(g.id(), f.id());
}

// Render and analyze place, size and order particles by the time, the spacing and the positions: a
// frame with a NaN or an infinity there (or a spacing that is not positive) is refused, saying what.
TEST(Frames, ATimeSpacingOrPositionThatIsNotFiniteIsRefused) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const auto message = [](const Frame& f) { return error_of([&] { frame_from_npz(frame_to_npz(f), "frames/f.npz"); }); };
  Frame f = small_frame();
  f.position()[3] = nan;  // particle 1's y
  EXPECT_NE(message(f).find("frames/f.npz: not a sluice frame: the position of particle id 1 (row 1 of x) is not "
                            "finite: [1, nan]"),
            std::string::npos)
      << message(f);
  f = small_frame();
  f.position()[4] = -inf;
  EXPECT_NE(message(f).find("the position of particle id 2 (row 2 of x) is not finite: [-inf, 2.5]"), std::string::npos)
      << message(f);
  for (const double t : {nan, inf}) {
    f = small_frame();
    f.time = t;
    EXPECT_NE(message(f).find(fmt::format("frames/f.npz: not a sluice frame: its time t = {} is not finite", t)),
              std::string::npos)
        << message(f);
  }
  for (const double dx : {0.0, -0.025, nan, inf}) {
    f = small_frame();
    f.dx = dx;
    EXPECT_NE(message(f).find(fmt::format("frames/f.npz: not a sluice frame: dx = {} is not a positive spacing", dx)),
              std::string::npos)
        << message(f);
  }
  // Other fields may hold anything a run can: a NaN velocity is read back.
  f = small_frame();
  f.velocity()[0] = nan;
  EXPECT_TRUE(std::isnan(frame_from_npz(frame_to_npz(f), "f.npz").velocity()[0]));
}

TEST(Frames, NpzOfTheSameFrameIsTheSameBytes) {
  // No timestamps: identical runs write identical files (the restart test relies on it).
  EXPECT_EQ(frame_to_npz(small_frame()), frame_to_npz(small_frame()));
}

TEST(Frames, TruncatedNpzIsAClearError) {
  const std::string bytes = frame_to_npz(small_frame());
  for (std::size_t keep : {std::size_t{0}, std::size_t{10}, std::size_t{100}, bytes.size() / 2, bytes.size() - 1}) {
    const std::string message = error_of([&] { frame_from_npz(bytes.substr(0, keep), "frames/f.npz"); });
    EXPECT_NE(message.find("frames/f.npz: not a sluice frame"), std::string::npos) << keep << ": " << message;
  }
}

TEST(Frames, FlippedDataByteIsAChecksumError) {
  std::string bytes = frame_to_npz(small_frame());
  // Inside the data of the last array ("body"), just before the central directory.
  const auto directory = bytes.find("PK\x01\x02");
  ASSERT_NE(directory, std::string::npos);
  bytes[directory - 3] = static_cast<char>(bytes[directory - 3] ^ 0x40);
  const std::string message = error_of([&] { frame_from_npz(bytes, "frames/f.npz"); });
  EXPECT_NE(message.find("frames/f.npz"), std::string::npos) << message;
  EXPECT_NE(message.find("body.npy: checksum mismatch"), std::string::npos) << message;
}

TEST(Frames, EveryFlippedByteIsDetectedOrHarmlessNeverACrash) {
  const Frame f = small_frame();
  const std::string good = frame_to_npz(f);
  int detected = 0;
  for (std::size_t at = 0; at < good.size(); ++at) {
    std::string bytes = good;
    bytes[at] = static_cast<char>(bytes[at] ^ 0xFF);
    try {
      const Frame g = frame_from_npz(bytes, "f.npz");
      // Only bytes that carry no data (zip dates, versions, attributes) may go unnoticed: never wrong values.
      EXPECT_EQ(g.time, f.time) << at;
      EXPECT_EQ(g.step, f.step) << at;
      EXPECT_EQ(g.dx, f.dx) << at;
      EXPECT_EQ(g.position(), f.position()) << at;
      EXPECT_EQ(g.velocity(), f.velocity()) << at;
      EXPECT_EQ(g.density(), f.density()) << at;
      EXPECT_EQ(g.pressure(), f.pressure()) << at;
      EXPECT_EQ(g.kind(), f.kind()) << at;
      EXPECT_EQ(g.id(), f.id()) << at;
    } catch (const FormatError& e) {
      EXPECT_NE(std::string(e.what()).find("f.npz: not a sluice frame"), std::string::npos) << e.what();
      ++detected;
    }
  }
  // Everything inside the arrays (headers and data) is covered by the zip CRC-32s: most of the file.
  EXPECT_GT(detected, static_cast<int>(good.size() * 3 / 4));
}

// What a sink received: every chunk, and where the chunks' bytes were.
struct ChunkLog {
  std::string bytes;
  std::size_t largest = 0;
  std::vector<const char*> starts;
  ByteSink sink() {
    return [this](std::string_view b) {
      bytes += b;
      largest = std::max(largest, b.size());
      starts.push_back(b.data());
    };
  }
};

Frame frame_of(std::size_t n) {
  Frame f;
  f.time = 0.5;
  f.step = 7;
  f.dx = 0.01;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = 0.01 * static_cast<double>(i % 100), y = 0.01 * static_cast<double>(i / 100);
    f.position().insert(f.position().end(), {x, y});
    f.velocity().insert(f.velocity().end(), {0.1 * x, -y});
    f.density().push_back(1000.0 + x);
    f.pressure().push_back(9.81 * y);
    f.kind().push_back(i % 7 == 0 ? 1 : 0);
    f.id().push_back(static_cast<std::uint32_t>(i));
    f.body().push_back(i % 7 == 0 ? 1 : 0);
  }
  return f;
}

TEST(Frames, AreStreamedFromTheFrameWithoutACopyOfTheFile) {
  // A run writes each frame straight into its file: no chunk holds more than one array, the .npz
  // arrays are passed on from the frame's own memory, and the .vtu pads its 2D vectors to three
  // components a block at a time. (Built whole in memory, a frame of a million particles took 400 MB.)
  const std::size_t n = 20000;
  const Frame f = frame_of(n);
  const std::size_t one_array = n * 2 * sizeof(double);  // the largest array, positions or velocities

  ChunkLog npz;
  write_frame_npz(f, npz.sink());
  EXPECT_EQ(npz.bytes, frame_to_npz(f));
  EXPECT_GT(npz.bytes.size(), 3 * one_array);
  EXPECT_LE(npz.largest, one_array);
  EXPECT_NE(std::find(npz.starts.begin(), npz.starts.end(), reinterpret_cast<const char*>(f.position().data())),
            npz.starts.end());
  const Frame g = frame_from_npz(npz.bytes, "streamed.npz");
  EXPECT_EQ(g.position(), f.position());
  EXPECT_EQ(g.id(), f.id());

  ChunkLog vtu;
  write_frame_vtu(f, vtu.sink());
  EXPECT_EQ(vtu.bytes, frame_to_vtu(f));
  EXPECT_GT(vtu.bytes.size(), 5 * one_array);
  EXPECT_LE(vtu.largest, one_array);  // the padded vectors would be 1.5 times this whole
}

TEST(Frames, VtuDeclaresEveryFieldAndItsAppendedBlocksFit) {
  const Frame f = small_frame();
  const std::string vtu = frame_to_vtu(f);
  for (const char* name :
       {"velocity", "density", "pressure", "kind", "id", "body", "Points", "connectivity", "offsets", "types"})
    EXPECT_NE(vtu.find(fmt::format("Name=\"{}\"", name)), std::string::npos) << name;
  EXPECT_NE(vtu.find("NumberOfPoints=\"3\""), std::string::npos);
  EXPECT_NE(vtu.find("<AppendedData encoding=\"raw\">"), std::string::npos);
  // The last block (cell types, UInt8) ends right before the closing of AppendedData.
  const auto start = vtu.find('_', vtu.find("<AppendedData")) + 1;
  const auto end = vtu.rfind("\n  </AppendedData>");
  std::size_t at = start, blocks = 0;
  while (at < end) {
    std::uint64_t size = 0;
    std::memcpy(&size, vtu.data() + at, sizeof size);
    at += sizeof size + size;
    ++blocks;
  }
  EXPECT_EQ(at, end);
  EXPECT_EQ(blocks, 10u);
}

TEST(Frames, HoldTheRegistrysFrameFieldsWithThePressureAfterTheDensity) {
  std::vector<std::string> registry;
  const Particles<2> none;
  Particles<2>::fields(none, [&](const FieldSpec& spec, const auto&) {
    if (spec.has(field_role::frame)) registry.emplace_back(spec.name);
    if (spec.name == "density") registry.emplace_back("pressure");
  });
  std::vector<std::string> names, short_names;
  for (const FrameField& field : Frame().fields) {
    names.push_back(field.name);
    short_names.push_back(field.short_name);
  }
  EXPECT_EQ(names, registry);
  EXPECT_EQ(names, (std::vector<std::string>{"position", "velocity", "density", "pressure", "kind", "id", "body"}));
  EXPECT_EQ(short_names, (std::vector<std::string>{"x", "v", "rho", "p", "kind", "id", "body"}));

  // A frame of a run: every field in particle-id order, the pressure from the equation of state.
  Simulation sim(tiny_case(), 1);
  for (int i = 0; i < 25; ++i) sim.step();  // reordered by cell, moving
  const Frame f = make_frame(sim);
  const Particles<2>& p = sim.particles<2>();
  ASSERT_EQ(f.size(), p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::size_t row = p.id[i];
    EXPECT_EQ(f.id()[row], p.id[i]);
    EXPECT_EQ(f.position()[2 * row + 1], p.position[1][i]);
    EXPECT_EQ(f.velocity()[2 * row], p.velocity[0][i]);
    EXPECT_EQ(f.density()[row], p.density[i]);
    EXPECT_DOUBLE_EQ(f.pressure()[row], sim.eos().pressure(p.density[i]));
    EXPECT_EQ(f.kind()[row], static_cast<std::uint8_t>(p.kind[i]));
    EXPECT_EQ(f.body()[row], p.is_fluid(i) ? body_id::water : body_id::tank);
  }
  // The .npz holds them in that order after t, step and dx; the .vtu names each one.
  const std::string npz = frame_to_npz(f);
  std::size_t at = 0;
  for (const std::string name : {"t", "step", "dx", "x", "v", "rho", "p", "kind", "id", "body"}) {
    const auto next = npz.find(name + ".npy", at);
    ASSERT_NE(next, std::string::npos) << name;
    at = next + name.size() + 4;
  }
  const std::string vtu = frame_to_vtu(f);
  for (const std::string name : {"velocity", "density", "pressure", "kind", "id", "body"})
    EXPECT_NE(vtu.find(fmt::format("Name=\"{}\"", name)), std::string::npos) << name;
  EXPECT_THROW((void)f.values<double>("no_such_field"), std::out_of_range);
  EXPECT_THROW((void)f.values<double>("kind"), std::out_of_range);  // stored as bytes
}

TEST(Frames, PvdListsEachFrameWithItsTime) {
  const std::string pvd = pvd_text({{0.0, "frames/frame_000000.vtu"}, {0.30000000000000004, "frames/frame_000003.vtu"}});
  EXPECT_NE(pvd.find("<VTKFile type=\"Collection\""), std::string::npos);
  EXPECT_NE(pvd.find("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"frames/frame_000000.vtu\"/>"),
            std::string::npos)
      << pvd;
  // Times are written exactly (shortest round-trip form), so they match the frames' own times.
  EXPECT_NE(pvd.find("timestep=\"0.30000000000000004\" group=\"\" part=\"0\" file=\"frames/frame_000003.vtu\""),
            std::string::npos)
      << pvd;
}

class CheckpointFile : public ::testing::Test {
 protected:
  void SetUp() override {
    sim_ = std::make_unique<Simulation>(tiny_case(), 1);
    for (int i = 0; i < 25; ++i) sim_->step();  // a state that is not the initial one (reordered, moving)
    bytes_ = checkpoint_bytes(*sim_, 12.5);
  }
  std::unique_ptr<Simulation> sim_;
  std::string bytes_;
};

// zlib's crc32 takes at most 4 GiB - 1 bytes a call. The checkpoint reader once passed it the whole
// file's length cast to 32 bits, so a checkpoint of 4 GiB or more was checked over its length modulo
// 4 GiB and refused as damaged. The bytes here are 4 GiB + 8: 64 MiB of zeros in one memory file,
// mapped 64 times one after the other (64 MiB of memory in all), then one private page, where the
// CRC goes (and the damage). The expected CRC is built independently of crc32_of, by zlib's
// crc32_combine64 doubling the CRC of 1 MiB of zeros.
TEST(Checkpoint, ChecksumCoversFilesOf4GiBAndMore) {
  const std::size_t piece = std::size_t{64} << 20, pieces = 64, zeros = piece * pieces;
  const std::size_t payload = zeros + 4, n = payload + 4;
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  void* map = mmap(nullptr, zeros + page, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  ASSERT_NE(map, MAP_FAILED);
  const int fd = memfd_create("zeros", 0);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(ftruncate(fd, static_cast<off_t>(piece)), 0);
  for (std::size_t k = 0; k < pieces; ++k)
    ASSERT_NE(mmap(static_cast<char*>(map) + k * piece, piece, PROT_READ, MAP_SHARED | MAP_FIXED, fd, 0), MAP_FAILED);
  ASSERT_NE(mmap(static_cast<char*>(map) + zeros, page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED,
                 -1, 0),
            MAP_FAILED);
  close(fd);
  char* bytes = static_cast<char*>(map);
  std::size_t length = std::size_t{1} << 20;
  auto expected = static_cast<std::uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(bytes), static_cast<uInt>(length)));
  while (2 * length <= payload) {
    expected = static_cast<std::uint32_t>(crc32_combine64(expected, expected, static_cast<z_off64_t>(length)));
    length *= 2;
  }
  const auto tail = static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(bytes), static_cast<uInt>(payload - length)));
  expected = static_cast<std::uint32_t>(crc32_combine64(expected, tail, static_cast<z_off64_t>(payload - length)));
  const std::string_view all(bytes, n);
  EXPECT_EQ(crc32_of(0, all.substr(0, payload)), expected);
  std::memcpy(bytes + payload, &expected, sizeof expected);
  EXPECT_TRUE(checkpoint_checksum_matches(all));
  // The CRC of the length modulo 4 GiB, what the reader compared before, is another number.
  EXPECT_NE(crc32_of(0, all.substr(0, payload - (std::size_t{4} << 30))), expected);
  bytes[n - 5] = 1;  // damaged
  EXPECT_FALSE(checkpoint_checksum_matches(all));
  munmap(map, zeros + page);
}

TEST(Checkpoint, IsStreamedFromTheParticlesArrays) {
  // The particles' arrays go to the file as they are, with a running checksum: never the whole
  // checkpoint in one string.
  const Simulation sim(tiny_case(0.01), 1);
  ChunkLog log;
  write_checkpoint_bytes(sim, 12.5, log.sink());
  EXPECT_EQ(log.bytes, checkpoint_bytes(sim, 12.5));
  EXPECT_EQ(parse_checkpoint(log.bytes, "streamed.bin").clock.step, 0);
  const std::size_t n = sim.particle_count();
  const std::size_t head = case_template(sim.config()).size() + 256;  // the case's text and the clock
  EXPECT_LE(log.largest, std::max(n * sizeof(double), head));
  EXPECT_GT(log.bytes.size(), 4 * n * sizeof(double) + head);
}

TEST_F(CheckpointFile, RoundTripRestoresTheExactState) {
  const Checkpoint checkpoint = parse_checkpoint(bytes_, "checkpoint.bin");
  struct {
    Case config;
    Clock clock;
    Particles<2> particles;
    double wall_seconds;
  } cp{checkpoint.config, checkpoint.clock, std::get<Particles<2>>(checkpoint.particles), checkpoint.wall_seconds};
  const Particles<2>& p = sim_->particles<2>();
  EXPECT_EQ(case_template(cp.config), case_template(sim_->config()));
  EXPECT_EQ(cp.clock.time, sim_->clock().time);
  EXPECT_EQ(cp.clock.step, 25);
  EXPECT_EQ(cp.clock.last_dt, sim_->clock().last_dt);
  EXPECT_EQ(cp.clock.leaks, sim_->clock().leaks);
  EXPECT_EQ(cp.wall_seconds, 12.5);
  ASSERT_EQ(cp.particles.size(), p.size());
  for (int d = 0; d < 2; ++d) {
    EXPECT_EQ(cp.particles.position[d], p.position[d]);
    EXPECT_EQ(cp.particles.velocity[d], p.velocity[d]);
  }
  EXPECT_EQ(cp.particles.density, p.density);
  EXPECT_EQ(cp.particles.kind, p.kind);
  EXPECT_EQ(cp.particles.id, p.id);
  EXPECT_EQ(cp.particles.needs_density_repair, p.needs_density_repair);
}

TEST_F(CheckpointFile, ContinuingFromItIsBitForBitTheSame) {
  Checkpoint cp = parse_checkpoint(bytes_, "checkpoint.bin");
  Simulation resumed(cp.config, std::move(cp.particles), cp.clock, 1);
  for (int i = 0; i < 30; ++i) {
    sim_->step();
    resumed.step();
  }
  EXPECT_EQ(resumed.clock().time, sim_->clock().time);
  EXPECT_EQ(resumed.particles<2>().id, sim_->particles<2>().id);
  EXPECT_EQ(resumed.particles<2>().position[0], sim_->particles<2>().position[0]);
  EXPECT_EQ(resumed.particles<2>().position[1], sim_->particles<2>().position[1]);
  EXPECT_EQ(resumed.particles<2>().velocity[1], sim_->particles<2>().velocity[1]);
  EXPECT_EQ(resumed.particles<2>().density, sim_->particles<2>().density);
}

TEST_F(CheckpointFile, AFlippedByteIsAChecksumMismatch) {
  for (std::size_t at : {bytes_.size() / 3, bytes_.size() / 2, bytes_.size() - 10, bytes_.size() - 1}) {
    std::string bad = bytes_;
    bad[at] = static_cast<char>(bad[at] ^ 0x01);
    const std::string message = error_of([&] { parse_checkpoint(bad, "out/run/checkpoint.bin"); });
    EXPECT_NE(message.find("out/run/checkpoint.bin: not a usable checkpoint: checksum mismatch"), std::string::npos)
        << at << ": " << message;
  }
}

TEST_F(CheckpointFile, AnotherFormatVersionNamesBothVersions) {
  std::string other = bytes_;
  const std::uint32_t version = checkpoint_format_version + 1;
  std::memcpy(other.data() + 8, &version, sizeof version);
  const std::string message = error_of([&] { parse_checkpoint(other, "old.bin"); });
  EXPECT_NE(message.find("old.bin"), std::string::npos) << message;
  EXPECT_NE(message.find(fmt::format("format version {}, this sluice reads versions 2 to {}", version,
                                     checkpoint_format_version)),
            std::string::npos)
      << message;
}

TEST_F(CheckpointFile, AVersionOneCheckpointIsAClearError) {
  std::string old = bytes_;
  const std::uint32_t version = 1;
  std::memcpy(old.data() + 8, &version, sizeof version);
  const std::string message = error_of([&] { parse_checkpoint(old, "old.bin"); });
  EXPECT_NE(message.find("old.bin: not a usable checkpoint: format version 1, written by an earlier sluice"),
            std::string::npos)
      << message;
}

// Version 6 (before floating bodies) is version 7 without their states' count after the absorbing
// pistons', version 5 (before absorbing pistons) version 6 without their states' count after the outflow,
// version 4 (before bodies) version 5 without the body field, version 3 (before outflow) version 4
// without the outflow count after the rates, and version 2
// (before the leapfrog) version 3 without the rates-carried byte after the clock: such files still
// restart, and continue exactly as the current file of the same state.
TEST_F(CheckpointFile, VersionTwoToSixCheckpointsAreStillRead) {
  ASSERT_FALSE(sim_->clock().rates_carried);
  const std::string stored_case = case_template(sim_->config());
  const std::size_t flag_at = 8 + 4 + 4 + 8 + stored_case.size() + 5 * 8;
  ASSERT_EQ(bytes_.substr(8 + 4 + 4 + 8, stored_case.size()), stored_case);
  ASSERT_EQ(bytes_[flag_at], '\0');
  ASSERT_EQ(bytes_.substr(flag_at + 1, 8), std::string(8, '\0'));  // no outflow
  ASSERT_EQ(bytes_.substr(flag_at + 9, 4), std::string(4, '\0'));   // no absorbing pistons
  ASSERT_EQ(bytes_.substr(flag_at + 13, 4), std::string(4, '\0'));  // no floating bodies
  const auto older = [&](std::uint32_t version) {
    std::string old = bytes_;
    old.erase(flag_at + 13, 4);
    if (version == 6) {
      std::memcpy(old.data() + 8, &version, sizeof version);
      return parse_checkpoint(with_crc_fixed(old), "v6.bin");
    }
    old.erase(flag_at + 9, 4);
    if (version == 5) {
      std::memcpy(old.data() + 8, &version, sizeof version);
      return parse_checkpoint(with_crc_fixed(old), "v5.bin");
    }
    // Before version 5, no body field: its block goes, and the field count drops by one.
    const std::size_t n = sim_->particles<2>().size();
    const auto body = old.find(std::string("\x04\x00" "body", 6));
    const auto count_at = old.find(std::string("\x08\x00" "position", 10)) - 4;
    if (body == std::string::npos) throw std::logic_error("no body field in the checkpoint");
    old.erase(body, 2 + 4 + 1 + 1 + n);
    std::uint32_t fields = 0;
    std::memcpy(&fields, old.data() + count_at, sizeof fields);
    --fields;
    std::memcpy(old.data() + count_at, &fields, sizeof fields);
    if (version == 4) {
      std::memcpy(old.data() + 8, &version, sizeof version);
      return parse_checkpoint(with_crc_fixed(old), "v4.bin");
    }
    old.erase(flag_at + 1, 8);
    if (version == 2) old.erase(flag_at, 1);
    std::memcpy(old.data() + 8, &version, sizeof version);
    return parse_checkpoint(with_crc_fixed(old), fmt::format("v{}.bin", version));
  };
  Checkpoint current = parse_checkpoint(bytes_, "v7.bin");
  Simulation from_current(current.config, std::move(current.particles), current.clock, 1);
  for (int i = 0; i < 10; ++i) from_current.step();
  for (std::uint32_t version : {2u, 3u, 4u, 5u, 6u}) {
    SCOPED_TRACE(version);
    Checkpoint old = older(version);
    EXPECT_FALSE(old.clock.rates_carried);
    EXPECT_EQ(old.clock.outflow, 0);
    EXPECT_EQ(old.clock.step, 25);
    Simulation from_old(old.config, std::move(old.particles), old.clock, 1);
    for (int i = 0; i < 10; ++i) from_old.step();
    EXPECT_EQ(from_old.particles<2>().velocity[1], from_current.particles<2>().velocity[1]);
    EXPECT_EQ(from_old.particles<2>().density, from_current.particles<2>().density);
  }
}

// The leapfrog's checkpoint also holds the rates it carries into the next step (acceleration and
// density_rate, after the other fields) and their summary; carried rates with another integrator are
// refused.
TEST(LeapfrogCheckpoint, HoldsTheCarriedRatesAndTheirSummary) {
  Case c = tiny_case();
  c.integrator = Integrator::leapfrog;
  Simulation sim(c, 1);
  for (int i = 0; i < 25; ++i) sim.step();
  ASSERT_TRUE(sim.clock().rates_carried);
  const std::string bytes = checkpoint_bytes(sim, 1.0);
  const auto repair = bytes.find("needs_density_repair");
  const auto acceleration = bytes.find("acceleration", repair);
  ASSERT_NE(repair, std::string::npos);
  ASSERT_NE(acceleration, std::string::npos);
  EXPECT_NE(bytes.find("density_rate", acceleration), std::string::npos);
  const Checkpoint cp = parse_checkpoint(bytes, "lf.bin");
  EXPECT_TRUE(cp.clock.rates_carried);
  EXPECT_EQ(cp.clock.rates.max_acceleration, sim.clock().rates.max_acceleration);
  EXPECT_EQ(cp.clock.rates.max_relative_speed, sim.clock().rates.max_relative_speed);
  EXPECT_EQ(cp.clock.rates.max_density, sim.clock().rates.max_density);
  EXPECT_EQ(cp.clock.rates.min_fluid_distance, sim.clock().rates.min_fluid_distance);
  const auto& p = std::get<Particles<2>>(cp.particles);
  EXPECT_EQ(p.acceleration[0], sim.particles<2>().acceleration[0]);
  EXPECT_EQ(p.acceleration[1], sim.particles<2>().acceleration[1]);
  EXPECT_EQ(p.density_rate, sim.particles<2>().density_rate);

  // The same bytes with the stored case's integrator renamed (same length) and the CRC fixed.
  std::string other = bytes;
  const auto at = other.find("integrator = \"leapfrog\"");
  ASSERT_NE(at, std::string::npos);
  other.replace(at, 23, "integrator = \"euler\"   ");
  const std::string message = error_of([&] { parse_checkpoint(with_crc_fixed(other), "x.bin"); });
  EXPECT_NE(message.find("x.bin: not a usable checkpoint: rates carried over with the euler integrator"),
            std::string::npos)
      << message;
}

TEST_F(CheckpointFile, TheFieldTableNamesEachFieldOfTheRegistry) {
  // Every field the registry marks for checkpoints is stored under its name, in registry order.
  // The table follows the stored case, whose comments may use the same words.
  const std::string stored_case = case_template(sim_->config());
  const auto case_at = bytes_.find(stored_case);
  ASSERT_NE(case_at, std::string::npos);
  std::size_t from = case_at + stored_case.size();
  std::size_t velocity = std::string::npos;
  Particles<2>::fields(sim_->particles<2>(), [&](const FieldSpec& f, const auto&) {
    if (!f.has(field_role::checkpoint)) return;
    const auto at = bytes_.find(std::string(f.name), from);
    EXPECT_NE(at, std::string::npos) << f.name;
    if (f.name == std::string_view("velocity")) velocity = at;
    from = at;
  });
  ASSERT_NE(velocity, std::string::npos);
  // A field renamed in the file is refused with both names.
  std::string renamed = bytes_;
  renamed.replace(velocity, 8, "velocitx");
  const std::string message = error_of([&] { parse_checkpoint(with_crc_fixed(renamed), "r.bin"); });
  EXPECT_NE(message.find("field 'velocitx' where 'velocity' was expected"), std::string::npos) << message;
}

// Text read from the file reaches the message escaped: a field name holding a terminal's escape
// sequence (colour, or worse) is shown as \u001B, never sent to the terminal.
TEST_F(CheckpointFile, AFieldNameFromTheFileIsShownEscaped) {
  const std::string stored_case = case_template(sim_->config());
  const auto velocity = bytes_.find("velocity", bytes_.find(stored_case) + stored_case.size());
  ASSERT_NE(velocity, std::string::npos);
  std::string renamed = bytes_;
  renamed.replace(velocity, 8, "\x1b[31m\x9b\xffv");  // same length: ESC [ 3 1 m, a C1 byte, a non-UTF-8 byte, v
  const std::string message = error_of([&] { parse_checkpoint(with_crc_fixed(renamed), "r.bin"); });
  EXPECT_NE(message.find(R"(r.bin: not a usable checkpoint: field '\u001B[31m\x9B\xFFv' where 'velocity' was expected)"),
            std::string::npos)
      << message;
  for (const char c : message) EXPECT_FALSE(static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) << message;
}

TEST_F(CheckpointFile, TruncatedOrForeignFilesAreClearErrors) {
  for (std::size_t keep : {bytes_.size() - 1, bytes_.size() / 2, std::size_t{100}}) {
    const std::string message = error_of([&] { parse_checkpoint(bytes_.substr(0, keep), "c.bin"); });
    EXPECT_NE(message.find("c.bin: not a usable checkpoint: checksum mismatch (the file is damaged or incomplete)"),
              std::string::npos)
        << keep << ": " << message;
  }
  for (const std::string& junk : {std::string(), std::string("SLUICE"), std::string("time,step\n0,0\n1,2\n3,4\n")}) {
    const std::string message = error_of([&] { parse_checkpoint(junk, "c.bin"); });
    EXPECT_NE(message.find("c.bin: not a usable checkpoint: it does not start with the sluice checkpoint signature"),
              std::string::npos)
        << message;
  }
}

// A checkpoint is input like a case file: a value no run can hold is refused (CaseError: exit status
// 2), even where the checksum passes (a file made or altered by hand).
namespace {

// Where the data of a stored particle field starts: after its name, element type and component count.
std::size_t field_data_at(const std::string& bytes, const Case& stored, std::string_view name) {
  const std::string text = case_template(stored);
  const auto case_at = bytes.find(text);
  if (case_at == std::string::npos) return std::string::npos;
  const std::string key = std::string(1, static_cast<char>(name.size())) + '\0' + std::string(name);
  const auto at = bytes.find(key, case_at + text.size());
  return at == std::string::npos ? at : at + key.size() + 2;
}

template <class F>
std::string case_error_of(F&& f) {
  try {
    f();
  } catch (const CaseError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("(not a CaseError) ") + e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_F(CheckpointFile, ANonFiniteParticleValueIsRefused) {
  const std::size_t n = sim_->particle_count();
  const std::size_t velocity = field_data_at(bytes_, sim_->config(), "velocity");
  const std::size_t position = field_data_at(bytes_, sim_->config(), "position");
  const std::size_t density = field_data_at(bytes_, sim_->config(), "density");
  ASSERT_NE(velocity, std::string::npos);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const struct {
    std::size_t at;
    double value;
    const char* expected;
  } cases[] = {
      {velocity + (n + 3) * sizeof(double), nan, "velocity component y is nan"},
      {position + 5 * sizeof(double), inf, "position component x is inf"},
      {density + 7 * sizeof(double), -1.0, "density -1 (id "},
      {density + 8 * sizeof(double), 0.0, "density 0 (id "},
  };
  for (const auto& c : cases) {
    std::string bad = bytes_;
    std::memcpy(bad.data() + c.at, &c.value, sizeof(double));
    const std::string message = case_error_of([&] { parse_checkpoint(with_crc_fixed(bad), "nan.bin"); });
    EXPECT_NE(message.find("nan.bin: not a usable checkpoint: "), std::string::npos) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
  }
}

TEST_F(CheckpointFile, AStepCountNearTheLargestIntegerIsRefused) {
  const std::string text = case_template(sim_->config());
  const std::size_t step_at = bytes_.find(text) + text.size() + sizeof(double);
  for (const std::int64_t step : {std::numeric_limits<std::int64_t>::max(), kLargestCount + 1, std::int64_t{-1}}) {
    std::string bad = bytes_;
    std::memcpy(bad.data() + step_at, &step, sizeof step);
    const std::string message = case_error_of([&] { parse_checkpoint(with_crc_fixed(bad), "steps.bin"); });
    EXPECT_NE(message.find(fmt::format("steps.bin: not a usable checkpoint: impossible clock (time {}, step {},",
                                       sim_->time(), step)),
              std::string::npos)
        << message;
  }
  std::string largest = bytes_;
  std::memcpy(largest.data() + step_at, &kLargestCount, sizeof kLargestCount);
  EXPECT_EQ(parse_checkpoint(with_crc_fixed(largest), "ok.bin").clock.step, kLargestCount);
}

// The particles must be those the stored case makes: another dx (the stored case edited), a moved
// wall particle or a water particle turned into wall are refused when the run is set up from it.
TEST_F(CheckpointFile, ParticlesThatTheStoredCaseDoesNotMakeAreRefused) {
  const std::string text = case_template(sim_->config());
  const auto dx_at = bytes_.find("dx = 0.1\n", bytes_.find(text));
  ASSERT_NE(dx_at, std::string::npos);
  std::string other_dx = bytes_;
  other_dx.replace(dx_at, 9, "dx = 0.2\n");
  Checkpoint cp = parse_checkpoint(with_crc_fixed(other_dx), "dx.bin");
  std::string message = case_error_of([&] { Simulation(cp.config, std::move(cp.particles), cp.clock, 1); });
  EXPECT_NE(message.find(fmt::format("{} particles, where its case (domain.dx = 0.2 m) builds", sim_->particle_count())),
            std::string::npos)
      << message;

  const Particles<2>& p = sim_->particles<2>();
  std::size_t wall = 0, water = 0;
  while (p.is_fluid(wall)) ++wall;
  while (!p.is_fluid(water)) ++water;
  const std::size_t position = field_data_at(bytes_, sim_->config(), "position");
  std::string moved = bytes_;
  const double x = p.position[0][wall] + 0.01;
  std::memcpy(moved.data() + position + wall * sizeof(double), &x, sizeof x);
  cp = parse_checkpoint(with_crc_fixed(moved), "moved.bin");
  message = case_error_of([&] { Simulation(cp.config, std::move(cp.particles), cp.clock, 1); });
  EXPECT_NE(message.find(fmt::format("wall particle id {} is at (", p.id[wall])), std::string::npos) << message;

  const std::size_t kind = field_data_at(bytes_, sim_->config(), "kind");
  std::string turned = bytes_;
  turned[kind + water] = static_cast<char>(Kind::wall);
  cp = parse_checkpoint(with_crc_fixed(turned), "kind.bin");
  message = case_error_of([&] { Simulation(cp.config, std::move(cp.particles), cp.clock, 1); });
  EXPECT_NE(message.find(fmt::format("particle id {} is a wall particle, where its case has water", p.id[water])),
            std::string::npos)
      << message;

  // The checkpoint as written restarts.
  cp = parse_checkpoint(bytes_, "good.bin");
  EXPECT_NO_THROW(Simulation(cp.config, std::move(cp.particles), cp.clock, 1));
}

// A restart from a state the instability guard refuses (here a density of 3 rho0, which reads as a
// positive finite number) is refused before anything is written, naming the file and the particle.
TEST_F(CheckpointFile, ARestartFromAStateTheGuardRefusesWritesNothing) {
  TempDir dir;
  const std::size_t density = field_data_at(bytes_, sim_->config(), "density");
  std::string bad = bytes_;
  const double rho = 3.0 * sim_->config().rest_density;
  std::memcpy(bad.data() + density + 4 * sizeof(double), &rho, sizeof rho);
  const fs::path path = dir.path() / "checkpoint.bin";
  write_file_atomic(path, with_crc_fixed(bad));
  RunOptions options;
  options.restart = path;
  options.output_dir = dir.path() / "out";
  options.progress = RunOptions::Progress::none;
  std::ostringstream log;
  const std::string message = case_error_of([&] { run_case(Case{}, options, log); });
  EXPECT_NE(message.find(path.string() + ": not a usable checkpoint: 1 particle is bad"), std::string::npos) << message;
  EXPECT_NE(message.find("density 3000 kg/m^3"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(options.output_dir));
}

TEST_F(CheckpointFile, WrittenAtomicallyAndReadBack) {
  TempDir dir;
  const fs::path path = dir.path() / "checkpoint.bin";
  write_checkpoint(path, *sim_, 12.5);
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"checkpoint.bin"});
  EXPECT_EQ(read_file(path), bytes_);
  EXPECT_EQ(read_checkpoint(path).clock.step, 25);
  const std::string missing = error_of([&] { read_checkpoint(dir.path() / "nope.bin"); });
  EXPECT_NE(missing.find("nope.bin: no such file"), std::string::npos) << missing;
}

TEST(AtomicFile, TheFinalNameAppearsOnlyOnCommit) {
  TempDir dir;
  const fs::path path = dir.path() / "out.txt";
  {
    AtomicFile f(path);
    f.write("hello");
    EXPECT_FALSE(fs::exists(path));
    const auto names = names_in(dir.path());
    ASSERT_EQ(names.size(), 1u);
    EXPECT_EQ(names[0], fmt::format("out.txt.tmp{}", ::getpid()));
    f.commit();
  }
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"out.txt"});
  EXPECT_EQ(read_file(path), "hello");
  write_file_atomic(path, "replaced");
  EXPECT_EQ(read_file(path), "replaced");
}

TEST(AtomicFile, AnAbandonedFileLeavesNothingBehind) {
  TempDir dir;
  write_file_atomic(dir.path() / "keep.txt", "old");
  {
    AtomicFile f(dir.path() / "keep.txt");
    f.write("new but never committed");
  }
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"keep.txt"});
  EXPECT_EQ(read_file(dir.path() / "keep.txt"), "old");
}

TEST(AtomicFile, AnUnwritableDirectoryIsAnIoErrorNamingThePath) {
  TempDir dir;
  write_file_atomic(dir.path() / "a_file", "x");
  // Tests may run as root, for whom permissions do not block: use paths no one can create files in.
  for (const fs::path& path : {fs::path("/proc/sluice_no_such_dir/frame.npz"), dir.path() / "a_file" / "frame.npz"}) {
    try {
      write_file_atomic(path, "data");
      ADD_FAILURE() << "no error writing " << path;
    } catch (const IoError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path.string() + ": cannot create ("), std::string::npos) << message;
    }
  }
  const std::string message = error_of([&] { create_directories_or_throw(dir.path() / "a_file" / "sub"); });
  EXPECT_NE(message.find("a_file/sub: cannot create directory"), std::string::npos) << message;
}

TEST(AtomicFile, AFullDiskIsAnIoErrorAndLeavesNoFile) {
  // A file-size limit makes writes fail with EFBIG, as a full disk fails them with ENOSPC.
  TempDir dir;
  std::signal(SIGXFSZ, SIG_IGN);
  rlimit old{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  rlimit limited = old;
  limited.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
  const std::string message = error_of([&] { write_file_atomic(dir.path() / "big.bin", std::string(100000, 'x')); });
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &old), 0);
  EXPECT_NE(message.find("big.bin: cannot write (File too large)"), std::string::npos) << message;
  EXPECT_TRUE(names_in(dir.path()).empty());
}

TEST(AtomicFile, StaleTemporaryFilesOfDeadProcessesAreRemoved) {
  TempDir dir;
  const fs::path d = dir.path();
  // pid 999999999 is above any pid Linux hands out (pid_max <= 2^22).
  for (const std::string& name : std::vector<std::string>{"frame_000001.npz.tmp999999999", "diagnostics.csv.tmp999999998",
                                                          fmt::format("mine.csv.tmp{}", ::getpid()), "notes.tmpx",
                                                          "data.tmp", "frame.npz"})
    write_file_atomic(d / name, "x");
  EXPECT_EQ(remove_stale_temp_files(d), 2u);
  EXPECT_EQ(names_in(d), (std::vector<std::string>{"data.tmp", "frame.npz", fmt::format("mine.csv.tmp{}", ::getpid()),
                                                   "notes.tmpx"}));
  EXPECT_EQ(remove_stale_temp_files(d / "no_such_dir"), 0u);
}

ino_t inode_of(const fs::path& path) {
  struct stat s {};
  EXPECT_EQ(::stat(path.c_str(), &s), 0) << path;
  return s.st_ino;
}

TEST(AppendFile, RecordsGoInBeforeTheFooterOfTheSameFile) {
  TempDir dir;
  const fs::path path = dir.path() / "list.xml";
  AppendFile file(path, "<list>\n", "</list>\n");
  EXPECT_FALSE(fs::exists(path));  // nothing until the first records
  file.append("  <a/>\n");
  EXPECT_EQ(read_file(path), "<list>\n  <a/>\n</list>\n");
  const ino_t inode = inode_of(path);
  file.append("  <b/>\n  <c/>\n");
  file.append("");
  file.append("  <d/>\n");
  EXPECT_EQ(read_file(path), "<list>\n  <a/>\n  <b/>\n  <c/>\n  <d/>\n</list>\n");
  EXPECT_EQ(inode_of(path), inode);  // the same file, grown: not a new one renamed over it
  file.sync();
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"list.xml"});
}

TEST(AppendFile, TheFirstAppendCreatesTheFileEvenWithNoRecords) {
  TempDir dir;
  AppendFile file(dir.path() / "series.csv", "time,height\n");
  file.append("");
  EXPECT_EQ(read_file(dir.path() / "series.csv"), "time,height\n");
}

TEST(AppendFile, ResumeKeepsTheSameFileOrReplacesWhatDiffers) {
  TempDir dir;
  const fs::path path = dir.path() / "series.csv";
  write_file_atomic(path, "time,height\n0,1\n0.1,2\n");
  const ino_t inode = inode_of(path);
  AppendFile file(path, "time,height\n");
  file.resume("time,height\n0,1\n0.1,2\n");
  EXPECT_EQ(inode_of(path), inode);
  file.append("0.2,3\n");
  EXPECT_EQ(read_file(path), "time,height\n0,1\n0.1,2\n0.2,3\n");
  EXPECT_EQ(inode_of(path), inode);

  AppendFile again(path, "time,height\n");
  again.resume("time,height\n0,1\n");  // what a restart at t = 0 keeps
  again.append("0.1,5\n");
  EXPECT_EQ(read_file(path), "time,height\n0,1\n0.1,5\n");
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"series.csv"});
}

TEST(AppendFile, AFailedAppendIsAnIoErrorAndLeavesTheFileAsItWas) {
  // Past a file-size limit the write stops part way (then fails with EFBIG), as on a full disk.
  TempDir dir;
  const fs::path path = dir.path() / "list.xml";
  AppendFile file(path, "<list>\n", "</list>\n");
  file.append("  <a/>\n");
  std::signal(SIGXFSZ, SIG_IGN);
  rlimit old{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  rlimit limited = old;
  limited.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
  std::string records;
  while (records.size() < 10000) records += "  <b/>\n";
  const std::string message = error_of([&] { file.append(records); });
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &old), 0);
  EXPECT_NE(message.find("list.xml: cannot write (File too large)"), std::string::npos) << message;
  EXPECT_EQ(read_file(path), "<list>\n  <a/>\n</list>\n");
  file.append("  <c/>\n");  // and it goes on from there once there is room
  EXPECT_EQ(read_file(path), "<list>\n  <a/>\n  <c/>\n</list>\n");
}

TEST(Probes, CsvRowsUntilKeepsTheHeaderAndEarlierRows) {
  const std::string csv = "time,height\n0,1\n0.1,1.5\n0.2,2\n0.30000000000000004,2.5\n";
  EXPECT_EQ(csv_rows_until(csv, 0.2), "time,height\n0,1\n0.1,1.5\n0.2,2\n");
  EXPECT_EQ(csv_rows_until(csv, 0.0), "time,height\n0,1\n");
  EXPECT_EQ(csv_rows_until(csv, 10.0), csv);
  // A damaged row ends the kept rows; a last row without its newline was cut off in the middle of a write.
  EXPECT_EQ(csv_rows_until("time,height\n0,1\nx\n0.2,2\n", 1.0), "time,height\n0,1\n");
  EXPECT_EQ(csv_rows_until("time,height\n0,1\n0.1,1.", 1.0), "time,height\n0,1\n");
  EXPECT_EQ(csv_rows_until("time,height\n0,1\n0.1", 1.0), "time,height\n0,1\n");
  EXPECT_EQ(csv_rows_until("time,hei", 1.0), "");
}

TEST(Probes, HeadersNameTheColumns) {
  Probe p;
  p.type = ProbeType::pressure;
  EXPECT_EQ(probe_header(p, 2), "time,pressure,neighbours");
  p.type = ProbeType::gauge;
  EXPECT_EQ(probe_header(p, 2), "time,height");
  p.type = ProbeType::front;
  EXPECT_EQ(probe_header(p, 2), "time,distance,x,y");
  EXPECT_EQ(probe_header(p, 3), "time,distance,x,y,z");
}
