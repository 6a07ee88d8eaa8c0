// A damaged video end to end: the test writes a short Motion JPEG video of the golden frame with
// FFmpeg's libraries, zeroes the bytes of two frames' JPEGs and cuts the file inside the last
// frame. The video source skips the zeroed frames (CorruptFrameError) and goes on; `patlab live`
// on the file finishes with exit status 0, its --stats counting the skipped frames.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "../test_util.h"
#include "patlab/live/frame_source.h"
#include "patlab/vision/frame_io.h"
#include "video_writer.h"

namespace patlab::live {
namespace {

using patlab::testing::kGoldenFrame;
constexpr int kFrames = 6;

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Where each frame's JPEG starts (SOI followed by a marker) and ends (after EOI) in the file.
std::vector<std::pair<size_t, size_t>> Jpegs(const std::string& bytes) {
  std::vector<std::pair<size_t, size_t>> jpegs;
  for (size_t at = bytes.find("\xff\xd8\xff"); at != std::string::npos;
       at = bytes.find("\xff\xd8\xff", at + 3)) {
    const size_t eoi = bytes.find("\xff\xd9", at);
    if (eoi == std::string::npos) break;
    jpegs.emplace_back(at, eoi + 2);
  }
  return jpegs;
}

// The video written, frames 2 and 4 zeroed, the file cut halfway through frame 5.
std::string DamagedVideo(const patlab::testing::TempDir& dir) {
  const std::string path = dir.Path("damaged.mkv");
  const camera::Image golden = vision::ReadFrame(kGoldenFrame + "png");
  EXPECT_TRUE(testing::WriteMjpegVideo(path, std::vector<camera::Image>(kFrames, golden), 30));
  std::string bytes = ReadBytes(path);
  const auto jpegs = Jpegs(bytes);
  EXPECT_EQ(jpegs.size(), static_cast<size_t>(kFrames));
  if (jpegs.size() != kFrames) return path;
  for (int damaged : {2, 4}) {
    const auto [from, to] = jpegs[static_cast<size_t>(damaged)];
    std::fill(bytes.begin() + static_cast<std::ptrdiff_t>(from),
              bytes.begin() + static_cast<std::ptrdiff_t>(to), '\0');
  }
  bytes.resize((jpegs[5].first + jpegs[5].second) / 2);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  return path;
}

TEST(CorruptVideo, DamagedFramesAreSkippedAndReadingGoesOn) {
  patlab::testing::TempDir dir;
  std::unique_ptr<FrameSource> source = OpenVideoFile(DamagedVideo(dir));
  std::string outcomes;  // per call: F a frame, C a corrupt frame, E a source error, . the end
  SourceFrame frame;
  for (int call = 0; call < 3 * kFrames; ++call) {
    try {
      if (!source->Next(&frame)) {
        outcomes += '.';
        break;
      }
      outcomes += 'F';
    } catch (const CorruptFrameError&) {
      outcomes += 'C';
    } catch (const SourceError&) {
      outcomes += 'E';
      break;
    }
  }
  // Frames 0, 1, 3 read, 2 and 4 skipped; the cut frame 5 is dropped by the demuxer (the file
  // ends inside its block), so the stream ends there.
  EXPECT_EQ(outcomes, "FFCFC.");
}

TEST(CorruptVideo, LiveRunFinishesAndCountsTheSkippedFrames) {
  patlab::testing::TempDir dir;
  const std::string video = DamagedVideo(dir);
  const patlab::testing::CommandResult r = patlab::testing::RunCommand(
      std::string(PATLAB_BINARY) + " live " + video + " --rate max -t " + kGoldenFrame +
      "thresholds.toml -c " + kGoldenFrame + "calibration.toml -s " + kGoldenFrame +
      "detector.toml --send 127.0.0.1:9 --stats");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("frames received 3, "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(", skipped corrupt 2;"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("damaged.mkv): " + video + ": frame 2 skipped: "), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("damaged.mkv): " + video + ": frame 4 skipped: "), std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace patlab::live
