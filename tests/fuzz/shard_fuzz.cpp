// Shard files of `patlab simulate --shard K/N` (sim/shard.h) read and checked by the merge. An
// input starting with 'F' is forged: the rest, if it is a JSON object, gets its checksum
// recomputed, so the fuzzer reaches the checks of fields and values behind the checksum.
#include <unistd.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "fuzz_util.h"
#include "patlab/sim/shard.h"
#include "patlab/sim/shard_internal.h"

namespace {

// One file per process, rewritten for each input (MergeShards reads files).
const std::string& ShardPath() {
  static const std::string path =
      "/tmp/patlab-shard-fuzz-" + std::to_string(::getpid()) + ".shard-1-of-1.json";
  return path;
}

std::string Forged(const std::string& text) {
  nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object()) return text;
  j["checksum"] = patlab::sim::shard_detail::Checksum(j);
  return j.dump(1);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text = patlab::fuzz::Text(data, size);
  if (!text.empty() && text[0] == 'F') text = Forged(text.substr(1));
  std::ofstream(ShardPath(), std::ios::binary | std::ios::trunc) << text;
  patlab::fuzz::ExpectInputErrorOnly(
      [&] { (void)patlab::sim::MergeShards({ShardPath()}, "/nonexistent/out", ""); });
  return 0;
}
