// SSL log files (live/ssl_log.h): the bytes of a written log against the format written out by
// hand, messages read back, a log cut inside its last message, and files that are no log.
#include "patlab/live/ssl_log.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "../expect_error.h"
#include "../test_util.h"

namespace patlab::live {
namespace {

using patlab::testing::ReadFile;
using patlab::testing::TempDir;

TEST(SslLog, BytesAreTheFormat) {
  TempDir dir;
  const std::string path = dir.Path("a.log");
  {
    SslLogWriter writer(path);
    writer.Write(0x0102030405060708, SslMessageType::kVision2010, "abc");
  }
  const std::string expected = std::string("SSL_LOG_FILE") + std::string("\0\0\0\1", 4) +
                               std::string("\1\2\3\4\5\6\7\x08", 8) + std::string("\0\0\0\2", 4) +
                               std::string("\0\0\0\3", 4) + "abc";
  EXPECT_EQ(ReadFile(path), expected);
}

TEST(SslLog, ReadsBackMessageForMessage) {
  TempDir dir;
  const std::string path = dir.Path("b.log");
  SslLogWriter writer(path);
  writer.Write(1, SslMessageType::kVision2010, "one");
  writer.Write(-2, SslMessageType::kRefbox2013, "");
  writer.Write(3, SslMessageType::kVision2010, std::string(100000, 'x'));
  // Each message is in the file as soon as Write returns, before Close.
  const SslLog log = ReadSslLog(path);
  writer.Close();
  ASSERT_EQ(log.messages.size(), 3u);
  EXPECT_EQ(log.messages[0].receive_time_ns, 1);
  EXPECT_EQ(log.messages[0].type, 2);
  EXPECT_EQ(log.messages[0].bytes, "one");
  EXPECT_EQ(log.messages[1].receive_time_ns, -2);
  EXPECT_EQ(log.messages[1].type, 3);
  EXPECT_EQ(log.messages[1].bytes, "");
  EXPECT_EQ(log.messages[2].bytes, std::string(100000, 'x'));
  EXPECT_EQ(log.truncated, 0);
}

TEST(SslLog, CutLastMessageIsDroppedAndCounted) {
  TempDir dir;
  const std::string path = dir.Path("c.log");
  {
    SslLogWriter writer(path);
    writer.Write(1, SslMessageType::kVision2010, "whole");
    writer.Write(2, SslMessageType::kVision2010, "cut short");
  }
  const auto size = std::filesystem::file_size(path);
  // The last record is 16 + 9 bytes: cut inside its bytes, then inside its head.
  for (const uintmax_t cut : {uintmax_t{3}, uintmax_t{14}}) {
    std::filesystem::resize_file(path, size - cut);
    const SslLog log = ReadSslLog(path);
    ASSERT_EQ(log.messages.size(), 1u);
    EXPECT_EQ(log.messages[0].bytes, "whole");
    EXPECT_EQ(log.truncated, 1);
  }
}

TEST(SslLog, RejectsFilesThatAreNoLog) {
  TempDir dir;
  EXPECT_INPUT_ERROR(ReadSslLog(dir.Write("d.log", "SSL_LOG_FILX\0\0\0\1")),
                     dir.Path("d.log") +
                         ": byte 0: the file does not start with SSL_LOG_FILE; expected an SSL "
                         "log file");
  EXPECT_INPUT_ERROR(ReadSslLog(dir.Write("e.log", std::string("SSL_LOG_FILE\0\0\0\2", 16))),
                     dir.Path("e.log") + ": byte 12: version is 2; expected 1");
  const std::string negative = std::string("SSL_LOG_FILE\0\0\0\1", 16) + std::string(8, '\0') +
                               std::string("\0\0\0\2\xff\xff\xff\xfe", 8);
  EXPECT_INPUT_ERROR(ReadSslLog(dir.Write("f.log", negative)),
                     dir.Path("f.log") + ": byte 28: message size is -2; expected >= 0");
  EXPECT_INPUT_ERROR(
      ReadSslLog(dir.Path("missing.log")),
      dir.Path("missing.log") + ": cannot open the log; expected a readable SSL log file");
}

}  // namespace
}  // namespace patlab::live
