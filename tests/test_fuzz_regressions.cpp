// Inputs the fuzzers found (tests/fuzz_regressions/<target>/<name>), replayed through the same
// checks the fuzz targets run (fuzz/targets.hpp): each must be accepted or refused with the parser's
// documented error type (CaseError, FormatError), never crash, throw anything else, or break a
// round-trip property. Under the asan preset the sanitizers also check every replay.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

#include <zlib.h>

#include "targets.hpp"

namespace fs = std::filesystem;
using namespace sluice;

namespace {

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

std::vector<fs::path> inputs_of(const std::string& target) {
  const fs::path dir = fs::path(SLUICE_SOURCE_DIR) / "tests" / "fuzz_regressions" / target;
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

template <class Check>
void replay(const std::string& target, Check check) {
  const auto files = inputs_of(target);
  ASSERT_FALSE(files.empty()) << "no inputs in tests/fuzz_regressions/" << target;
  for (const auto& file : files) {
    const std::string bytes = read_bytes(file);
    try {
      check(bytes);
    } catch (const std::exception& e) {
      ADD_FAILURE() << target << "/" << file.filename().string() << ": " << typeid(e).name() << ": " << e.what();
    } catch (...) {
      ADD_FAILURE() << target << "/" << file.filename().string() << ": an exception not derived from std::exception";
    }
  }
}

// A zip archive with one stored entry, as parse_npz reads it.
std::string stored_zip(const std::string& name, const std::string& data) {
  auto put16 = [](std::string& out, std::uint16_t v) { out.append(reinterpret_cast<const char*>(&v), 2); };
  auto put32 = [](std::string& out, std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  const auto crc = static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(data.data()), static_cast<uInt>(data.size())));
  const auto size = static_cast<std::uint32_t>(data.size());
  std::string zip, directory;
  put32(zip, 0x04034b50);
  for (std::uint16_t v : {20, 0, 0, 0, 0}) put16(zip, v);  // version, flags, stored, time, date
  put32(zip, crc);
  put32(zip, size);
  put32(zip, size);
  put16(zip, static_cast<std::uint16_t>(name.size()));
  put16(zip, 0);
  zip += name + data;
  put32(directory, 0x02014b50);
  for (std::uint16_t v : {20, 20, 0, 0, 0, 0}) put16(directory, v);  // made by, needed, flags, stored, time, date
  put32(directory, crc);
  put32(directory, size);
  put32(directory, size);
  for (std::uint16_t v : {static_cast<std::uint16_t>(name.size()), std::uint16_t{0}, std::uint16_t{0},
                          std::uint16_t{0}, std::uint16_t{0}})
    put16(directory, v);  // name, extra, comment, disk, internal attributes
  put32(directory, 0);    // external attributes
  put32(directory, 0);    // offset of the local header
  directory += name;
  const auto directory_at = static_cast<std::uint32_t>(zip.size());
  zip += directory;
  put32(zip, 0x06054b50);
  for (std::uint16_t v : {0, 0, 1, 1}) put16(zip, v);
  put32(zip, static_cast<std::uint32_t>(directory.size()));
  put32(zip, directory_at);
  put16(zip, 0);
  return zip;
}

}  // namespace

TEST(FuzzRegressions, CaseInputs) { replay("case", fuzz::check_case); }
TEST(FuzzRegressions, CheckpointInputs) { replay("checkpoint", fuzz::check_checkpoint); }
TEST(FuzzRegressions, FrameInputs) { replay("frame", fuzz::check_frame); }
TEST(FuzzRegressions, MeshInputs) { replay("mesh", fuzz::check_mesh); }

// Hostile meshes get a clear MeshError before anything is allocated for what they claim: a binary STL
// header claiming two billion triangles (100 GB) in a file of 134 bytes; one claiming more triangles
// than a mesh may have; a file too short for a binary header that is not ASCII either.
TEST(FuzzRegressions, AHostileBinaryStlIsRefusedByItsHeader) {
  auto message_of = [](const std::string& bytes) -> std::string {
    try {
      check_closed_mesh(read_mesh(bytes, "m.stl"));
    } catch (const MeshError& e) {
      return e.what();
    }
    return "(accepted)";
  };
  auto binary = [](std::uint32_t count, std::size_t body) {
    std::string b(80, '\0');
    b.append(reinterpret_cast<const char*>(&count), 4);
    return b + std::string(body, '\0');
  };
  EXPECT_EQ(message_of(binary(2'000'000'000u, 50)),
            "a binary STL whose header says 2000000000 triangles (100000000084 bytes), in a file of 134 bytes; "
            "expected a complete binary STL, or ASCII STL (which starts with \"solid\")");
  EXPECT_NE(message_of(std::string(40, 'x')).find("40 bytes, too short for a binary STL"), std::string::npos);
  // A header that matches its size reaches the reader and the checks (one triangle with its corners at 0).
  EXPECT_NE(message_of(binary(1, 50)).find("degenerate"), std::string::npos) << message_of(binary(1, 50));
  EXPECT_EQ(fuzz::check_mesh(binary(2'000'000'000u, 50)), fuzz::Outcome::rejected);
  // The closed tetrahedron among the kept inputs is accepted, so the replay reaches the solid's queries.
  const std::string tetrahedron = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
  EXPECT_EQ(fuzz::check_mesh(tetrahedron), fuzz::Outcome::accepted);
  // Material statements are read past (sluice reads geometry only; assimp 5.2 crashed on some).
  EXPECT_EQ(fuzz::check_mesh("mtllib cube.mtl\n  usemtl steel\n" + tetrahedron), fuzz::Outcome::accepted);
}

// Found by reading parse_npy while fuzzing (the fuzzer itself did not reach it): its std::regex
// matching recursed once per header character, so a long .npy header overflowed the stack: a crash
// under ASan from about 40 kB, and `sluice render` of a frame with a 1 MB header died with SIGSEGV.
TEST(FuzzRegressions, ALongNpyHeaderIsAFormatErrorNotAStackOverflow) {
  const std::size_t n = 4'000'000;
  std::string repeated_dims;
  for (std::size_t i = 0; i < n / 3; ++i) repeated_dims += "1, ";
  const std::vector<std::string> headers = {
      "{'descr': '" + std::string(n, 'a') + "', 'fortran_order': False, 'shape': (), }",
      "{'descr': '<f8', 'fortran_order': False, 'shape': (" + repeated_dims + "), }",
      "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::string(n, ' ') + "), }",
  };
  for (const auto& header : headers) {
    const auto length = static_cast<std::uint32_t>(header.size());
    std::string npy = "\x93NUMPY\x02";
    npy += '\0';
    npy.append(reinterpret_cast<const char*>(&length), 4);
    npy += header;
    const std::string npz = stored_zip("x.npy", npy);
    EXPECT_THROW(parse_npz(npz), FormatError);
    EXPECT_EQ(fuzz::check_frame(npz), fuzz::Outcome::rejected);
  }
}

// The replay would pass vacuously if the checks let everything through: they do reject garbage with
// the documented error, and they see past the checksums the way the fuzzers do.
TEST(FuzzRegressions, ChecksRejectGarbageWithTheDocumentedError) {
  EXPECT_EQ(fuzz::check_case("[domain]\ndx = \"x\"\n"), fuzz::Outcome::rejected);
  EXPECT_THROW(parse_case("[domain]\ndx = \"x\"\n", "t.toml"), CaseError);
  EXPECT_EQ(fuzz::check_checkpoint("not a checkpoint"), fuzz::Outcome::rejected);
  EXPECT_THROW(parse_checkpoint("not a checkpoint", "t.bin"), FormatError);
  EXPECT_EQ(fuzz::check_frame("not an npz"), fuzz::Outcome::rejected);
  EXPECT_THROW(frame_from_npz("not an npz", "t.npz"), FormatError);
}

TEST(FuzzRegressions, FixingTheChecksumsReachesTheParsingBehindThem) {
  Frame f;
  f.time = 0.5;
  f.step = 7;
  f.dx = 0.1;
  f.position() = {1.0, 2.0};
  f.velocity() = {0.0, -1.0};
  f.density() = {1000.0};
  f.pressure() = {0.0};
  f.kind() = {0};
  f.id() = {0};
  f.body() = {0};
  std::string npz = frame_to_npz(f);
  EXPECT_EQ(fuzz::check_frame(npz), fuzz::Outcome::accepted);
  // Change the time's value: the zip CRC no longer matches, until fixed.
  const auto npy = npz.find("\x93NUMPY", npz.find("t.npy"));
  ASSERT_NE(npy, std::string::npos);
  const auto header_length = static_cast<std::size_t>(static_cast<unsigned char>(npz[npy + 8])) +
                             256 * static_cast<std::size_t>(static_cast<unsigned char>(npz[npy + 9]));
  npz[npy + 10 + header_length + 7] ^= 0x01;  // the last byte of t's 8 data bytes
  EXPECT_THROW(frame_from_npz(npz, "t.npz"), FormatError);
  const Frame g = frame_from_npz(fuzz::with_npz_crcs_fixed(npz), "t.npz");
  EXPECT_NE(g.time, f.time);
  EXPECT_EQ(g.step, 7);

  // Signature, version 2, dimension 2, a case text length far past the end, then a checksum.
  std::string checkpoint = std::string("SLUICECK") + '\x02' + std::string(3, '\0') + '\x02' + std::string(3, '\0') +
                           std::string(8, '\x7f') + std::string(4, '\0');
  auto message_of = [](const std::string& bytes) -> std::string {
    try {
      parse_checkpoint(bytes, "t.bin");
    } catch (const FormatError& e) {
      return e.what();
    }
    return "(accepted)";
  };
  EXPECT_NE(message_of(checkpoint).find("checksum mismatch"), std::string::npos) << message_of(checkpoint);
  const std::string fixed = fuzz::with_checkpoint_crc_fixed(checkpoint);
  EXPECT_NE(message_of(fixed).find("truncated case text"), std::string::npos) << message_of(fixed);
}
