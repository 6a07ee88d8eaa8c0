// SSL log files, the RoboCup Small Size League's recording format (what ssl-logtools and the
// league's log players read): the 12 bytes "SSL_LOG_FILE", a 32-bit version (1), then per
// message a 64-bit receive time (ns since the Unix epoch), a 32-bit message type, a 32-bit size
// and that many bytes of the message; every integer big-endian and signed.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace patlab::live {

// The message types of the format (ssl-logtools' MessageType).
enum class SslMessageType : int32_t {
  kBlank = 0,
  kUnknown = 1,
  kVision2010 = 2,  // an SSL_WrapperPacket (what patlab writes)
  kRefbox2013 = 3,
  kVision2014 = 4,
  kVisionTracker2020 = 5,
  kIndex2021 = 6,
};

inline constexpr std::string_view kSslLogHeader = "SSL_LOG_FILE";
inline constexpr int32_t kSslLogVersion = 1;

struct SslLogMessage {
  int64_t receive_time_ns = 0;
  int32_t type = 0;  // SslMessageType, as the file holds it (unknown types are kept)
  std::string bytes;
};

// Writes a log. Each message is written by one write(2) of its whole record, not buffered in the
// process: a process killed at any moment (SIGKILL) leaves a log that reads back to its last
// whole message, with at most a part of one more (which the reader drops).
class SslLogWriter {
 public:
  // Creates or truncates `path` and writes the header. EnvironmentError when it cannot.
  explicit SslLogWriter(const std::string& path);
  ~SslLogWriter();
  SslLogWriter(const SslLogWriter&) = delete;
  SslLogWriter& operator=(const SslLogWriter&) = delete;

  // EnvironmentError when the system does not take the record (disk full).
  void Write(int64_t receive_time_ns, SslMessageType type, std::string_view bytes);
  // Closes the file (also done by the destructor); EnvironmentError when close fails.
  void Close();
  long messages() const { return messages_; }

 private:
  void WriteAll(const std::string& record);
  std::string path_;
  int fd_ = -1;
  long messages_ = 0;
};

// Reads a log message by message. InputError "<path>: byte N: what; expected what" for a file
// that is no SSL log (header, version, a negative size); a last message cut short (the writer
// killed mid-record) ends the log and is counted in truncated(), not an error.
class SslLogReader {
 public:
  explicit SslLogReader(const std::string& path);
  // The next whole message; false at the end.
  bool Next(SslLogMessage* message);
  // 1 when the log ended inside a message (dropped), else 0.
  int truncated() const { return truncated_; }

 private:
  bool ReadExactly(char* out, size_t n);
  std::string path_;
  std::ifstream in_;
  uint64_t offset_ = 0;
  int truncated_ = 0;
};

// Every whole message of a log, and whether a cut last one was dropped.
struct SslLog {
  std::vector<SslLogMessage> messages;
  int truncated = 0;
};
SslLog ReadSslLog(const std::string& path);

}  // namespace patlab::live
