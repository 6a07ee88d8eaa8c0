// SSL log files (ssl_log.h).
#include "patlab/live/ssl_log.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "patlab/core/error.h"

namespace patlab::live {

namespace {

void PutBigEndian(uint64_t value, int bytes, std::string* out) {
  for (int i = bytes - 1; i >= 0; --i) out->push_back(static_cast<char>((value >> (8 * i)) & 0xff));
}

uint64_t GetBigEndian(const char* in, int bytes) {
  uint64_t value = 0;
  for (int i = 0; i < bytes; ++i) value = (value << 8) | static_cast<uint8_t>(in[i]);
  return value;
}

int32_t GetInt32(const char* in) { return static_cast<int32_t>(GetBigEndian(in, 4)); }

}  // namespace

SslLogWriter::SslLogWriter(const std::string& path) : path_(path) {
  fd_ = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw EnvironmentError(path + ": cannot create the log: " + std::strerror(errno));
  }
  std::string header(kSslLogHeader);
  PutBigEndian(static_cast<uint32_t>(kSslLogVersion), 4, &header);
  WriteAll(header);
}

SslLogWriter::~SslLogWriter() {
  if (fd_ >= 0) close(fd_);
}

void SslLogWriter::WriteAll(const std::string& record) {
  size_t done = 0;
  while (done < record.size()) {
    const ssize_t n = write(fd_, record.data() + done, record.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw EnvironmentError(path_ + ": cannot write: " + std::strerror(errno));
    done += static_cast<size_t>(n);
  }
}

void SslLogWriter::Write(int64_t receive_time_ns, SslMessageType type, std::string_view bytes) {
  if (fd_ < 0) throw EnvironmentError(path_ + ": the log is closed");
  std::string record;
  record.reserve(16 + bytes.size());
  PutBigEndian(static_cast<uint64_t>(receive_time_ns), 8, &record);
  PutBigEndian(static_cast<uint32_t>(type), 4, &record);
  PutBigEndian(static_cast<uint32_t>(bytes.size()), 4, &record);
  record.append(bytes);
  WriteAll(record);
  ++messages_;
}

void SslLogWriter::Close() {
  if (fd_ < 0) return;
  const int fd = fd_;
  fd_ = -1;
  if (close(fd) != 0) throw EnvironmentError(path_ + ": cannot close: " + std::strerror(errno));
}

SslLogReader::SslLogReader(const std::string& path) : path_(path), in_(path, std::ios::binary) {
  if (!in_) throw InputError(path + ": cannot open the log; expected a readable SSL log file");
  char header[16];
  const bool whole = ReadExactly(header, sizeof header);
  const std::string_view got(header, whole ? 12 : 0);
  if (!whole || got != kSslLogHeader) {
    throw InputError(path + ": byte 0: the file does not start with SSL_LOG_FILE; expected an " +
                     "SSL log file");
  }
  const int32_t version = GetInt32(header + 12);
  if (version != kSslLogVersion) {
    throw InputError(path + ": byte 12: version is " + std::to_string(version) + "; expected 1");
  }
}

bool SslLogReader::ReadExactly(char* out, size_t n) {
  in_.read(out, static_cast<std::streamsize>(n));
  const auto got = static_cast<size_t>(in_.gcount());
  offset_ += got;
  return got == n;
}

bool SslLogReader::Next(SslLogMessage* message) {
  char head[16];
  const uint64_t start = offset_;
  if (!ReadExactly(head, sizeof head)) {
    if (offset_ > start) truncated_ = 1;
    return false;
  }
  const int32_t size = GetInt32(head + 12);
  if (size < 0) {
    throw InputError(path_ + ": byte " + std::to_string(start + 12) + ": message size is " +
                     std::to_string(size) + "; expected >= 0");
  }
  message->receive_time_ns = static_cast<int64_t>(GetBigEndian(head, 8));
  message->type = GetInt32(head + 8);
  // Grown as it is read, so a size field larger than the file allocates no more than the file.
  message->bytes.clear();
  char chunk[65536];
  for (int32_t left = size; left > 0;) {
    const size_t n = std::min<size_t>(sizeof chunk, static_cast<size_t>(left));
    if (!ReadExactly(chunk, n)) {
      truncated_ = 1;
      return false;
    }
    message->bytes.append(chunk, n);
    left -= static_cast<int32_t>(n);
  }
  return true;
}

SslLog ReadSslLog(const std::string& path) {
  SslLogReader reader(path);
  SslLog log;
  SslLogMessage message;
  while (reader.Next(&message)) log.messages.push_back(message);
  log.truncated = reader.truncated();
  return log;
}

}  // namespace patlab::live
