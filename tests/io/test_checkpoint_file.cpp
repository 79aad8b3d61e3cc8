// Tests of the checkpoint container and the byte buffers: round trip, exact layout, and detection of
// every kind of damage (bad magic, other version, truncation, flipped bits, trailing bytes).
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "io/byte_buffer.hpp"
#include "io/checkpoint_file.hpp"
#include "mesodpd/spec.hpp"

namespace fs = std::filesystem;
using namespace mesodpd;

namespace {

class CheckpointTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("mesodpd_ckpt_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    path_ = dir_ / "run.ckpt";
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::vector<char> read_raw(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static void write_raw(const fs::path& p, const std::vector<char>& bytes) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }

  // The error must be a ConfigError naming the file and containing `needle`.
  void expect_rejected(const std::string& needle) const {
    try {
      (void)read_checkpoint_file(path_);
      FAIL() << "expected ConfigError containing '" << needle << "'";
    } catch (const ConfigError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path_.string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    }
  }

  static std::vector<std::byte> sample_payload() {
    ByteWriter w;
    w.put<std::uint64_t>(123456789012345ULL);
    w.put<double>(0.1 + 0.2);
    w.put<std::int32_t>(-7);
    w.put_vector(std::vector<double>{1.0 / 3.0, -2.5e-300, 6.02e23});
    w.put_vector(std::vector<std::uint32_t>{});
    w.put_string("species A");
    w.put_string(std::string("with\0nul", 8));
    return w.take();
  }

  fs::path dir_, path_;
};

TEST(Checksum, MatchesPublishedFnv1a64Vectors) {
  auto of = [](const std::string& s) {
    return checkpoint_checksum(std::as_bytes(std::span<const char>(s.data(), s.size())));
  };
  EXPECT_EQ(of(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(of("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(of("foobar"), 0x85944171f73967e8ULL);
}

TEST_F(CheckpointTest, RoundTripPreservesEveryValue) {
  const auto payload = sample_payload();
  write_checkpoint_file(path_, payload);
  const auto back = read_checkpoint_file(path_);
  ASSERT_EQ(back, payload);

  ByteReader r(back, "test payload");
  EXPECT_EQ(r.get<std::uint64_t>(), 123456789012345ULL);
  EXPECT_EQ(r.get<double>(), 0.1 + 0.2);
  EXPECT_EQ(r.get<std::int32_t>(), -7);
  EXPECT_EQ(r.get_vector<double>(), (std::vector<double>{1.0 / 3.0, -2.5e-300, 6.02e23}));
  EXPECT_TRUE(r.get_vector<std::uint32_t>().empty());
  EXPECT_EQ(r.get_string(), "species A");
  EXPECT_EQ(r.get_string(), std::string("with\0nul", 8));
  EXPECT_TRUE(r.at_end());
  EXPECT_NO_THROW(r.expect_end());
}

TEST_F(CheckpointTest, EmptyPayloadRoundTrips) {
  write_checkpoint_file(path_, {});
  EXPECT_TRUE(read_checkpoint_file(path_).empty());
  EXPECT_EQ(fs::file_size(path_), 16u + 4u + 8u + 8u);
}

TEST_F(CheckpointTest, FileLayoutIsAsDocumented) {
  const auto payload = sample_payload();
  write_checkpoint_file(path_, payload);
  const auto raw = read_raw(path_);
  ASSERT_EQ(raw.size(), 16 + 4 + 8 + payload.size() + 8);
  EXPECT_EQ(std::memcmp(raw.data(), "MESODPD-CKPT\0\0\0\0", 16), 0);
  std::uint32_t version = 0;
  std::uint64_t size = 0, checksum = 0;
  std::memcpy(&version, raw.data() + 16, 4);
  std::memcpy(&size, raw.data() + 20, 8);
  std::memcpy(&checksum, raw.data() + 28 + payload.size(), 8);
  EXPECT_EQ(version, kCheckpointFormatVersion);
  EXPECT_EQ(size, payload.size());
  EXPECT_EQ(std::memcmp(raw.data() + 28, payload.data(), payload.size()), 0);
  EXPECT_EQ(checksum, checkpoint_checksum(payload));
}

TEST_F(CheckpointTest, RewriteReplacesOldCheckpoint) {
  write_checkpoint_file(path_, sample_payload());
  const std::vector<std::byte> second(3, std::byte{0x5A});
  write_checkpoint_file(path_, second);
  EXPECT_EQ(read_checkpoint_file(path_), second);
}

TEST_F(CheckpointTest, MissingFileIsRejected) { expect_rejected("does not exist"); }

TEST_F(CheckpointTest, BadMagicIsRejected) {
  write_checkpoint_file(path_, sample_payload());
  auto raw = read_raw(path_);
  raw[3] = 'X';
  write_raw(path_, raw);
  expect_rejected("magic");
}

TEST_F(CheckpointTest, ForeignShortFileIsRejectedAsBadMagic) {
  write_raw(path_, {'h', 'e', 'l', 'l', 'o'});
  expect_rejected("magic");
}

TEST_F(CheckpointTest, UnsupportedVersionNamesBothVersions) {
  write_checkpoint_file(path_, sample_payload());
  auto raw = read_raw(path_);
  const std::uint32_t future = 7;
  std::memcpy(raw.data() + 16, &future, 4);
  write_raw(path_, raw);
  expect_rejected("version 7");
  expect_rejected("version " + std::to_string(kCheckpointFormatVersion));
}

TEST_F(CheckpointTest, EveryTruncationIsDetected) {
  write_checkpoint_file(path_, sample_payload());
  const auto raw = read_raw(path_);
  for (std::size_t len = 0; len < raw.size(); ++len) {
    SCOPED_TRACE("truncated to " + std::to_string(len) + " bytes");
    write_raw(path_, std::vector<char>(raw.begin(), raw.begin() + static_cast<std::ptrdiff_t>(len)));
    expect_rejected("truncated");
  }
}

TEST_F(CheckpointTest, FlippedPayloadBitIsDetectedByChecksum) {
  const auto payload = sample_payload();
  write_checkpoint_file(path_, payload);
  const auto raw = read_raw(path_);
  for (std::size_t k = 0; k < payload.size(); ++k) {
    SCOPED_TRACE("payload byte " + std::to_string(k));
    auto bad = raw;
    bad[28 + k] = static_cast<char>(bad[28 + k] ^ 0x01);
    write_raw(path_, bad);
    expect_rejected("checksum mismatch");
  }
}

TEST_F(CheckpointTest, FlippedChecksumByteIsDetected) {
  write_checkpoint_file(path_, sample_payload());
  auto raw = read_raw(path_);
  raw.back() = static_cast<char>(raw.back() ^ 0x80);
  write_raw(path_, raw);
  expect_rejected("checksum mismatch");
}

TEST_F(CheckpointTest, TrailingBytesAreRejected) {
  write_checkpoint_file(path_, sample_payload());
  auto raw = read_raw(path_);
  raw.push_back('!');
  write_raw(path_, raw);
  expect_rejected("unexpected bytes");
}

TEST(ByteReader, TruncatedValueNamesContextAndOffset) {
  const std::vector<std::byte> four(4);
  ByteReader r(four, "checkpoint 'x.ckpt' particles");
  try {
    (void)r.get<std::uint64_t>();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("checkpoint 'x.ckpt' particles"), std::string::npos) << msg;
    EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
  }
}

TEST(ByteReader, CorruptedHugeCountThrowsInsteadOfAllocating) {
  ByteWriter w;
  w.put<std::uint64_t>(~0ULL / 2);  // claims ~2^63 elements
  w.put<double>(1.0);
  const auto bytes = w.take();
  ByteReader r(bytes, "ctx");
  EXPECT_THROW((void)r.get_vector<double>(), ConfigError);
  ByteReader s(bytes, "ctx");
  EXPECT_THROW((void)s.get_string(), ConfigError);
}

TEST(ByteReader, ExpectEndRejectsTrailingBytes) {
  ByteWriter w;
  w.put<std::int32_t>(1);
  w.put<std::int32_t>(2);
  const auto bytes = w.take();
  ByteReader r(bytes, "ctx");
  EXPECT_EQ(r.get<std::int32_t>(), 1);
  EXPECT_THROW(r.expect_end(), ConfigError);
  EXPECT_EQ(r.get<std::int32_t>(), 2);
  EXPECT_NO_THROW(r.expect_end());
  EXPECT_THROW((void)r.get<std::uint8_t>(), ConfigError);
}

}  // namespace
