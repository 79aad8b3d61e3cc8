// Tests of write_file_atomically: content lands, failures leave the previous file and no debris.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"
#include "mesodpd/spec.hpp"

namespace fs = std::filesystem;
using mesodpd::ConfigError;
using mesodpd::write_file_atomically;

namespace {

// A fresh directory per test, removed afterwards.
class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("mesodpd_atomic_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static void write_plain(const fs::path& p, const std::string& s) {
    std::ofstream(p, std::ios::binary) << s;
  }

  // Files in the directory other than `keep`: temporaries must never survive.
  std::vector<std::string> others(const fs::path& keep) const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) {
      if (e.path() != keep) names.push_back(e.path().filename().string());
    }
    return names;
  }

  fs::path dir_;
};

TEST_F(AtomicFileTest, CreatesFileWithWriterContent) {
  const auto p = dir_ / "out.txt";
  write_file_atomically(p, [](std::ostream& out) { out << "hello\nworld\n"; });
  EXPECT_EQ(read(p), "hello\nworld\n");
  EXPECT_TRUE(others(p).empty());
}

TEST_F(AtomicFileTest, ReplacesExistingFile) {
  const auto p = dir_ / "out.txt";
  write_plain(p, "a much longer previous content that must disappear completely");
  write_file_atomically(p, [](std::ostream& out) { out << "new"; });
  EXPECT_EQ(read(p), "new");
  EXPECT_TRUE(others(p).empty());
}

TEST_F(AtomicFileTest, WriterExceptionLeavesOldFileIntactAndNamesPath) {
  const auto p = dir_ / "state.ckpt";
  write_plain(p, "old content");
  try {
    write_file_atomically(p, [](std::ostream& out) {
      out << "partial new content";
      out.flush();
      throw std::runtime_error("simulated failure in the middle");
    });
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("simulated failure"), std::string::npos) << msg;
  }
  EXPECT_EQ(read(p), "old content");
  EXPECT_TRUE(others(p).empty()) << "temporary file left behind";
}

TEST_F(AtomicFileTest, WriterExceptionCreatesNothingWhenFileWasAbsent) {
  const auto p = dir_ / "never.txt";
  EXPECT_THROW(write_file_atomically(p, [](std::ostream&) { throw 42; }), ConfigError);
  EXPECT_FALSE(fs::exists(p));
  EXPECT_TRUE(others(p).empty());
}

TEST_F(AtomicFileTest, MissingDirectoryIsAnErrorNamingThePath) {
  const auto p = dir_ / "no_such_dir" / "out.txt";
  try {
    write_file_atomically(p, [](std::ostream& out) { out << "x"; });
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(p));
}

TEST_F(AtomicFileTest, TargetIsADirectoryFailsAndKeepsIt) {
  const auto p = dir_ / "sub";
  fs::create_directory(p);
  write_plain(p / "inside", "keep");
  EXPECT_THROW(write_file_atomically(p, [](std::ostream& out) { out << "x"; }), ConfigError);
  EXPECT_TRUE(fs::is_directory(p));
  EXPECT_EQ(read(p / "inside"), "keep");
  EXPECT_TRUE(others(p).empty());
}

TEST_F(AtomicFileTest, BytesOverloadRoundTripsBinaryData) {
  const auto p = dir_ / "blob.bin";
  std::vector<std::byte> bytes;
  for (int k = 0; k < 1000; ++k) bytes.push_back(static_cast<std::byte>((k * 37) & 0xFF));  // includes zeros
  write_file_atomically(p, bytes);
  const std::string got = read(p);
  ASSERT_EQ(got.size(), bytes.size());
  for (std::size_t k = 0; k < bytes.size(); ++k) {
    ASSERT_EQ(static_cast<std::byte>(got[k]), bytes[k]) << "byte " << k;
  }
}

}  // namespace
