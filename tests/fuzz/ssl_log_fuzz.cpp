// SSL log files of `patlab live --log` (live/ssl_log.h) and the packets in them (live/packet.h):
// the reader on any bytes, then every message through ParsePacket and, for a whole log, the
// tracks of live/log_track.h.
#include <unistd.h>

#include <fstream>

#include "fuzz_util.h"
#include "patlab/live/log_track.h"
#include "patlab/live/packet.h"
#include "patlab/live/ssl_log.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The reader takes a path: the input goes to a file of this process.
  const std::string path = "/tmp/patlab_ssl_log_fuzz_" + std::to_string(getpid()) + ".log";
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  patlab::fuzz::ExpectInputErrorOnly([&] {
    const patlab::live::SslLog log = patlab::live::ReadSslLog(path);
    for (const patlab::live::SslLogMessage& m : log.messages) {
      (void)patlab::live::ParsePacket(m.bytes);
    }
    (void)patlab::live::TracksOfSslLog(path);
  });
  unlink(path.c_str());
  return 0;
}
