// Atomic file writing (file.h): a write leaves either the complete new file or the
// old one, never a temporary file, and every failure is an Error that starts with
// the target's path.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/base/file.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;
namespace fs = std::filesystem;

namespace {

// Every byte value, NULs and line ends included: nothing may be translated.
std::string allBytes() {
  std::string s;
  for (int i = 0; i < 256; ++i) s += static_cast<char>(i);
  return s + std::string("\r\n\n\r\0end\0", 10);
}

bool startsWith(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

// A directory holding one file, t.txt, whose content a failed write must leave as it is.
class FailedWrite : public testing::Test {
 protected:
  // The file has its old content and is alone: no temporary file is left.
  void expectUntouched() const {
    EXPECT_EQ(readFile(path), "old\n");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"t.txt"});
  }
  TempDir dir;
  const std::string path = dir.write("t.txt", "old\n");
};

}  // namespace

TEST(WriteFile, WritesExactlyTheBytes) {
  TempDir dir;
  const std::string path = dir.file("bytes.bin");
  writeTextFile(path, allBytes());
  EXPECT_EQ(readFile(path), allBytes());
  // More than the writer's buffer, written piecewise through the stream.
  std::string big;
  for (int i = 0; big.size() < 300000; ++i) big += std::to_string(i * 7919) + (i % 9 ? ' ' : '\n');
  writeFileAtomically(path, [&](std::ostream& out) {
    for (std::size_t at = 0; at < big.size(); at += 1000) out << big.substr(at, 1000);
  });
  EXPECT_EQ(readFile(path), big);
  // An empty file is a file.
  writeTextFile(dir.file("empty.txt"), "");
  EXPECT_TRUE(fs::exists(dir.file("empty.txt")));
  EXPECT_EQ(fs::file_size(dir.file("empty.txt")), 0u);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"bytes.bin", "empty.txt"}));
}

TEST(WriteFile, ReplacesTheOldFile) {
  TempDir dir;
  const std::string path = dir.write("t.txt", "an old and longer content\n");
  writeTextFile(path, "new\n");
  EXPECT_EQ(readFile(path), "new\n");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"t.txt"});
}

TEST_F(FailedWrite, AThrowingWriterLeavesTheOldFileAndNoTemporary) {
  // An Error that does not name the path gets it as a prefix; its text is kept.
  const std::string message = errorOf([&] {
    writeFileAtomically(path, [](std::ostream& out) {
      out << std::string(100000, 'x');  // some of it reaches the temporary file
      throw Error("the writer gave up");
    });
  });
  EXPECT_EQ(message, path + ": the writer gave up");
  expectUntouched();
  // One that names it already is passed on as it is.
  EXPECT_EQ(errorOf([&] {
              writeFileAtomically(path, [&](std::ostream&) { throw Error(path + ": line 3"); });
            }),
            path + ": line 3");
  // Any other exception passes through, with the same clean-up.
  EXPECT_THROW(writeFileAtomically(path,
                                   [](std::ostream& out) {
                                     out << "partial";
                                     throw std::runtime_error("not an osdmra::Error");
                                   }),
               std::runtime_error);
  expectUntouched();
}

TEST_F(FailedWrite, AFailedStreamIsAnError) {
  const std::string message = errorOf([&] {
    writeFileAtomically(path, [](std::ostream& out) {
      out << "half";
      out.setstate(std::ios::badbit);
    });
  });
  EXPECT_TRUE(startsWith(message, path + ": ")) << message;
  expectContains(message, {"write failed"});
  expectUntouched();
}

TEST(WriteFile, AnUnwritablePlaceIsAnErrorStartingWithThePath) {
  TempDir dir;
  // A directory that does not exist: no temporary file can be made there.
  const std::string missing = dir.file("missing/dir/t.txt");
  std::string message = errorOf([&] { writeTextFile(missing, "x"); });
  EXPECT_TRUE(startsWith(message, missing + ": ")) << message;
  expectContains(message, {"cannot create", "No such file or directory"});
  EXPECT_FALSE(fs::exists(dir.file("missing")));
  // A directory where the file should go: the temporary file is made next to it but
  // cannot replace it, and is removed.
  fs::create_directory(dir.file("taken"));
  const std::string taken = dir.file("taken");
  message = errorOf([&] { writeTextFile(taken, "x"); });
  EXPECT_TRUE(startsWith(message, taken + ": ")) << message;
  expectContains(message, {"cannot replace"});
  EXPECT_TRUE(fs::is_directory(taken));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"taken"});
  // A directory without write permission (not a barrier for root, who may write
  // anywhere: then the write succeeds, and that is checked instead).
  fs::create_directory(dir.file("locked"));
  const std::string locked = dir.file("locked/t.txt");
  ::chmod(dir.file("locked").c_str(), 0555);
  if (::access(dir.file("locked").c_str(), W_OK) != 0) {
    message = errorOf([&] { writeTextFile(locked, "x"); });
    EXPECT_TRUE(startsWith(message, locked + ": ")) << message;
    expectContains(message, {"cannot create", "Permission denied"});
    EXPECT_TRUE(fs::is_empty(dir.file("locked")));
  } else {
    writeTextFile(locked, "x");
    EXPECT_EQ(readFile(locked), "x");
  }
  ::chmod(dir.file("locked").c_str(), 0755);
}
