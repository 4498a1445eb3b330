// The data-file reader refuses every malformed file with "file:line: ..." naming the value, and
// reads back what write_data wrote bit for bit. AtomicFile leaves no temporary behind, not even
// when the process is killed by a signal, and check_output_paths sees one file under any name.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "allocation_probe.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/limits.hpp"

namespace hs = hardsphere;
namespace fs = std::filesystem;

namespace {

// A valid file; tests edit single lines (1-based numbers as in messages) and expect a refusal there.
std::vector<std::string> base_lines() {
  return {
      "test data",            // 1
      "",                     // 2
      "4 atoms",              // 3
      "2 atom types",         // 4
      "0 10 xlo xhi",         // 5
      "0 10 ylo yhi",         // 6
      "0 10 zlo zhi",         // 7
      "",                     // 8
      "Masses",               // 9
      "",                     // 10
      "1 1.0",                // 11
      "2 2.0",                // 12
      "",                     // 13
      "Atoms # sphere",       // 14
      "",                     // 15
      "1 1 1 1 1 1 1 0 0 0",  // 16
      "2 1 1 1 3 1 1 0 0 0",  // 17
      "3 2 1 1 1 3 1 0 0 0",  // 18
      "4 2 1 1 1 1 3 0 0 0",  // 19
      "",                     // 20
      "Velocities",           // 21
      "",                     // 22
      "1 0.1 0 0",            // 23
      "2 0 0.2 0",            // 24
      "3 0 0 0.3",            // 25
      "4 -0.1 -0.2 -0.3",     // 26
  };
}

std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

hs::ParticleSystem read(const std::string& text, std::array<bool, 3> periodic = {true, true, true}) {
  std::istringstream in(text);
  return hs::read_data(in, "t.data", periodic);
}

// Expects a refusal at `line` (-1: the file as a whole) whose message contains every needle.
void refused(const std::string& text, long line, std::initializer_list<const char*> needles,
             std::array<bool, 3> periodic = {true, true, true}) {
  try {
    read(text, periodic);
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const hs::InputError& e) {
    const std::string m = e.what();
    const std::string where = line < 0 ? "t.data: " : "t.data:" + std::to_string(line) + ": ";
    EXPECT_EQ(m.rfind(where, 0), 0u) << m;
    for (const char* n : needles) EXPECT_NE(m.find(n), std::string::npos) << "'" << n << "' not in: " << m;
  }
}

std::vector<std::string> with(std::vector<std::string> lines, std::size_t line, const std::string& text) {
  lines.at(line - 1) = text;
  return lines;
}

std::vector<std::string> without(std::vector<std::string> lines, std::size_t line) {
  lines.erase(lines.begin() + long(line) - 1);
  return lines;
}

std::vector<std::string> inserted(std::vector<std::string> lines, std::size_t before, const std::string& text) {
  lines.insert(lines.begin() + long(before) - 1, text);
  return lines;
}

}  // namespace

TEST(ReadData, BaseFileIsRead) {
  const auto s = read(join(base_lines()));
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s.id[3], 4);
  EXPECT_EQ(s.type[2], 2);
  EXPECT_EQ(s.vel[3].z, -0.3);
}

TEST(ReadData, VelocitiesMustCoverEveryAtomOnce) {
  // Atom 1 twice, atom 2 never: before, atom 2 silently kept v = 0.
  refused(join(with(base_lines(), 24, "1 0 0.2 0")), 24, {"atom id 1", "twice", "line 23"});
  // Fewer rows than atoms, then end of file or another section.
  refused(join(without(base_lines(), 26)), 25, {"Velocities section ends after 3 of 4 atoms"});
  auto moved = base_lines();
  moved.erase(moved.begin() + 8, moved.begin() + 13);  // Masses to the end, after 3 velocity rows
  moved.erase(moved.end() - 1);
  moved.insert(moved.end(), {"", "Masses", "", "1 1.0", "2 2.0"});
  refused(join(moved), 22, {"Velocities section ends after 3 of 4 atoms", "found section 'Masses'"});
  refused(join(with(base_lines(), 25, "3 0 zero 0.3")), 25, {"vy of atom 3", "'zero'"});
  refused(join(with(base_lines(), 25, "3 0 0 0.3 0 0 w")), 25, {"angular velocity", "'w'"});
  refused(join(with(base_lines(), 25, "9 0 0 0.3")), 25, {"unknown atom id 9"});
}

TEST(ReadData, ImageFlagsAreInt32) {
  refused(join(with(base_lines(), 17, "2 1 1 1 3 1 1 a b c")), 17, {"image flag of atom 2", "'a'"});
  refused(join(with(base_lines(), 17, "2 1 1 1 3 1 1 1e300 -5 7.5")), 17, {"'1e300'", "not an integer"});
  refused(join(with(base_lines(), 17, "2 1 1 1 3 1 1 0 -5 7.5")), 17, {"'7.5'"});
  refused(join(with(base_lines(), 17, "2 1 1 1 3 1 1 0 2147483648 0")), 17, {"'2147483648'", "32-bit"});
  refused(join(with(base_lines(), 17, "2 1 1 1 3 1 1 0 0 -99999999999999999999")), 17, {"-99999999999999999999"});
  // Valid flags are accepted and do not move the atom (the box wraps positions itself).
  const auto s = read(join(with(base_lines(), 17, "2 1 1 1 3 1 1 2147483647 -2147483648 1")));
  EXPECT_EQ(s.pos[1].x, 3);
}

TEST(ReadData, RepeatedHeaderLinesAreRefused) {
  refused(join(inserted(base_lines(), 5, "4 atoms")), 5, {"'atoms' appears twice", "line 3"});
  refused(join(inserted(base_lines(), 5, "3 atom types")), 5, {"'atom types' appears twice", "line 4"});
  refused(join(inserted(base_lines(), 8, "0 20 ylo yhi")), 8, {"'ylo yhi' appears twice", "line 6"});
  refused(join(inserted(inserted(base_lines(), 8, "0 bonds"), 8, "0 bonds")), 9, {"'bonds' appears twice", "line 8"});
}

TEST(ReadData, MassesRowsAreParsed) {
  // A short section used to be reported as "expected a section name".
  refused(join(without(base_lines(), 12)), 13,
          {"Masses section ends after 1 of 2 atom types", "found section 'Atoms'"});
  refused(join(with(base_lines(), 12, "2")), 12, {"mass line has 1 columns", "type mass"});
  refused(join(with(base_lines(), 12, "2 2.0 7")), 12, {"3 columns"});
  refused(join(with(base_lines(), 12, "3 2.0")), 12, {"atom type '3'", "2 atom types"});
  refused(join(with(base_lines(), 12, "0 2.0")), 12, {"atom type '0'"});
  refused(join(with(base_lines(), 12, "1 2.0")), 12, {"atom type 1 given twice", "line 11"});
  refused(join(with(base_lines(), 12, "2 0")), 12, {"mass 0 of atom type 2"});
  refused(join(with(base_lines(), 12, "2 -1")), 12, {"mass -1"});
  refused(join(with(base_lines(), 12, "2 nan")), 12, {"'nan'", "not a number"});
  // Only what LAMMPS reads: no hexadecimal floats or infinities (a file LAMMPS refuses).
  refused(join(with(base_lines(), 12, "2 0x1p0")), 12, {"'0x1p0'", "not a number", "LAMMPS"});
  refused(join(with(base_lines(), 12, "2 inf")), 12, {"'inf'", "not a number"});
  refused(join(with(base_lines(), 12, "2 1e999")), 12, {"'1e999'", "too large"});
  refused(join(with(base_lines(), 12, "2 heavy")), 12, {"'heavy'"});
  refused(join(inserted(base_lines(), 13, "3 3.0")), 13, {"expected a section name", "'3 3.0'", "atom types"});
}

TEST(ReadData, CountsAreBoundedAndNeverTrustedForAllocation) {
  refused(join(with(base_lines(), 3, "99999999999999 atoms")), 3, {"atom count '99999999999999'", "134217728"});
  refused(join(with(base_lines(), 3, "0 atoms")), 3, {"atom count '0'"});
  refused(join(with(base_lines(), 3, "-4 atoms")), 3, {"atom count '-4'"});
  refused(join(with(base_lines(), 3, "4.0 atoms")), 3, {"atom count '4.0'", "not an integer"});
  refused(join(with(base_lines(), 3, "4x atoms")), 3, {"'4x'"});
  refused(join(with(base_lines(), 3, "99999999999999999999 atoms")), 3, {"'99999999999999999999'"});
  refused(join(with(base_lines(), 4, "0 atom types")), 4, {"atom type count '0'"});
  refused(join(with(base_lines(), 4, "3000000000 atom types")), 4, {"'3000000000'"});
  // The largest accepted count with four rows: refused at the fifth, without reserving 2^27 atoms.
  {
    const test::LargestAllocation probe;
    refused(join(with(base_lines(), 3, std::to_string(hs::kMaxSpheres) + " atoms")), 21,
            {"Atoms section ends after 4 of 134217728 atoms", "found section 'Velocities'"});
    // A reservation sized by the header (2^27 atoms: gigabytes) would be far above this.
    EXPECT_LT(probe.bytes(), std::size_t(1) << 27);
  }
  refused(join(with(base_lines(), 3, "3 atoms")), 19, {"expected a section name", "'4 2 1 1 1 1 3 0 0 0'"});
}

TEST(ReadData, TrailingJunkAndNonNumbersAreRefused) {
  refused(join(with(base_lines(), 3, "4 atoms please")), 3, {"unknown header line '4 atoms please'"});
  refused(join(with(base_lines(), 5, "0 10 xlo xhi extra")), 5, {"unknown header line"});
  refused(join(with(base_lines(), 5, "0 10x xlo xhi")), 5, {"'10x'"});
  refused(join(with(base_lines(), 17, "2 1 1 1 3.0junk 1 1")), 17, {"x of atom 2", "'3.0junk'"});
  refused(join(with(base_lines(), 17, std::string("2 1 1 1 3\0junk 1 1", 18))), 17, {"x of atom 2", "not a number"});
  refused(join(with(base_lines(), 17, "2 1.5 1 1 3 1 1")), 17, {"atom type '1.5'"});
  refused(join(with(base_lines(), 17, "2 1 1 1 3 1e400 1")), 17, {"'1e400'", "too large"});
  refused(join(with(base_lines(), 17, "0 1 1 1 3 1 1")), 17, {"atom id '0'"});
  refused(join(with(base_lines(), 17, "2 1 1 1 3 1")), 17, {"6 columns"});
  refused(join(with(base_lines(), 14, "Atoms sphere")), 14, {"unexpected 'sphere'", "Atoms # sphere"});
  refused(join(with(base_lines(), 14, "Atoms # atomic")), 14, {"atom_style 'atomic'"});
  refused(join(inserted(base_lines(), 8, "junk junk types")), 8, {"unknown header line 'junk junk types'"});
  EXPECT_NO_THROW(read(join(inserted(base_lines(), 8, "2 bond types"))));
}

TEST(ReadData, SectionsAppearOnce) {
  auto twice = base_lines();
  twice.insert(twice.end(), {"", "Velocities", "", "1 0 0 0", "2 0 0 0", "3 0 0 0", "4 0 0 0"});
  refused(join(twice), 28, {"second Velocities section", "line 21"});
  auto masses = base_lines();
  masses.insert(masses.end(), {"", "Masses", "", "1 1", "2 1"});
  refused(join(masses), 28, {"second Masses section", "line 9"});
  refused(join(with(base_lines(), 21, "Bonds")), 21, {"section 'Bonds' is not supported"});
  auto early = base_lines();
  std::swap(early[13], early[20]);  // "Velocities" where "Atoms" was
  refused(join(early), 14, {"Velocities section before Atoms"});
}

TEST(ReadData, GeometryIsCheckedWithTheLine) {
  refused(join(with(base_lines(), 5, "-1e308 1e308 xlo xhi")), 5, {"overflows"});
  refused(join(with(base_lines(), 5, "10 0 xlo xhi")), 5, {"is empty"});
  refused(join(with(base_lines(), 19, "4 2 1 1 1 1 9.75 0 0 0")), 19,
          {"atom 4: z = 9.75 with radius", "outside the wall"}, {true, true, false});
  refused(join(with(base_lines(), 19, "4 2 5e-324 1 1 1 3")), 19, {"atom 4", "mass 0"});
  refused(join(with(base_lines(), 19, "4 2 4 1e308 1 1 3")), 19, {"mass inf"});
  refused(join(with(base_lines(), 19, "4 2 -1 1 1 1 3")), 19, {"diameter -1 of atom 4"});
  refused(join(with(base_lines(), 18, "1 2 1 1 1 3 1 0 0 0")), 18, {"atom id 1 appears twice", "line 16"});
  // A periodic y of length 8 against a sphere of diameter 4.5: both lines named; walls in y are fine.
  const auto wide = with(with(base_lines(), 6, "0 8 ylo yhi"), 18, "3 2 4.5 1 1 5 5 0 0 0");
  refused(join(wide), 6, {"along y", "largest diameter 4.5", "atom 3, line 18"});
  EXPECT_NO_THROW(read(join(wide), {true, false, true}));
}

TEST(ReadData, LongLinesAndEmptyInputAreRefused) {
  refused(std::string("title\n") + std::string(hs::kMaxDataLine + 10, '1'), 2, {"longer than 65536"});
  refused(std::string(hs::kMaxDataLine + 10, '\0'), 1, {"longer than"});
  refused("", -1, {"empty file"});
  refused("title only\n", 1, {"no 'N atoms' line"});
}

TEST(ReadData, WriteThenReadIsBitExactIncludingSubnormals) {
  auto s = read(join(base_lines()));
  s.vel[0] = {4.9406564584124654e-324, -1e-310, 2.2250738585072014e-308};  // strtod says ERANGE for these
  s.pos[1].y = 0.1 + 1e-16;
  std::ostringstream out;
  hs::write_data(out, s, "round trip");
  const auto back = read(out.str());
  ASSERT_EQ(back.size(), s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    EXPECT_EQ(back.id[i], s.id[i]);
    EXPECT_EQ(back.type[i], s.type[i]);
    EXPECT_EQ(back.radius[i], s.radius[i]);
    for (int d = 0; d < 3; ++d) {
      EXPECT_EQ(back.pos[i][d], s.pos[i][d]);
      EXPECT_EQ(back.vel[i][d], s.vel[i][d]);
    }
  }
}

// --- output files ---------------------------------------------------------------------------

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "hs_io_test_XXXXXX").string();
    path = ::mkdtemp(tmpl.data());
  }
  ~TempDir() { fs::remove_all(path); }
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST(AtomicFile, UncommittedLeavesNothingCommittedLeavesOnlyTheFile) {
  TempDir dir;
  {
    hs::AtomicFile f((dir.path / "a.txt").string());
    f.stream() << "partial";
    EXPECT_EQ(dir.entries().size(), 1u);  // the temporary
  }
  EXPECT_TRUE(dir.entries().empty());
  {
    hs::AtomicFile f((dir.path / "a.txt").string());
    f.stream() << "whole";
    f.commit();
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"a.txt"});
  EXPECT_EQ(slurp(dir.path / "a.txt"), "whole");
}

TEST(AtomicFile, OneFileUnderTwoNamesIsRefused) {
  TempDir dir;
  fs::create_directory(dir.path / "sub");
  hs::AtomicFile f((dir.path / "a.txt").string());
  EXPECT_THROW(hs::AtomicFile((dir.path / "sub" / ".." / "a.txt").string()), hs::InputError);
  EXPECT_THROW(hs::AtomicFile("/dev/null"), hs::InputError);
  EXPECT_THROW(hs::AtomicFile(dir.path.string()), hs::InputError);
}

TEST(AtomicFile, CommitTogetherRenamesAllOrLeavesNone) {
  TempDir dir;
  {
    hs::AtomicFile a((dir.path / "a").string()), b((dir.path / "b").string());
    a.stream() << 1;
    b.stream() << 2;
    hs::commit_together({&a, nullptr, &b});
  }
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a", "b"}));
}

TEST(AtomicFile, SignalRemovesTemporariesAndKillsWithThatSignal) {
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) {
    TempDir dir;
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      std::signal(sig, SIG_DFL);  // as a fresh process would have it
      hs::install_cleanup_signal_handlers();
      hs::AtomicFile a((dir.path / "a").string()), b((dir.path / "b").string());
      a.stream() << "x";
      a.stream().flush();
      ::raise(sig);
      ::_exit(0);  // not reached: the handler re-raises with the default action
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status)) << "signal " << sig << " status " << status;
    if (WIFSIGNALED(status)) {
      EXPECT_EQ(WTERMSIG(status), sig);
    }
    EXPECT_TRUE(dir.entries().empty()) << "signal " << sig << ": " << dir.entries().size() << " files left";
  }
}

TEST(CheckOutputPaths, SameFileUnderAnySpellingIsRefused) {
  TempDir dir;
  fs::create_directory(dir.path / "sub");
  const std::string x = (dir.path / "x").string();
  fs::create_symlink(dir.path / "x", dir.path / "link");  // dangling until x exists
  const std::vector<std::string> spellings = {x, (dir.path / "." / "x").string(),
                                              (dir.path / "sub" / ".." / "x").string(), (dir.path / "link").string()};
  for (const auto& other : spellings) {
    try {
      hs::check_output_paths({{"--json", x}, {"--dump", other}});
      ADD_FAILURE() << other << " accepted";
    } catch (const hs::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("same file"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(other), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(hs::check_output_paths({{"--json", x}, {"--dump", (dir.path / "y").string()}}));
  EXPECT_THROW(hs::check_output_paths({{"--dump", (dir.path / "sub").string()}}), hs::InputError);
  EXPECT_THROW(hs::check_output_paths({{"--dump", (dir.path / "nodir" / "x").string()}}), hs::InputError);
  EXPECT_THROW(hs::check_output_paths({{"--dump", ""}}), hs::InputError);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"link", "sub"}));  // nothing created
}
