// Shared helpers of the tests that write scratch frame files or read the shared real frames
// (vision, camera, render and design tests).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "expect_error.h"
#include "patlab/camera/image.h"
#include "patlab/core/error.h"

namespace patlab::vision::testing {

// A fresh scratch directory per test.
inline std::string ScratchDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "patlab_vision_test" /
                                    (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

inline void WriteBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

inline void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// An RGB frame k times larger, each pixel a k x k block of its colour: binned k x k
// (camera::BinImage), it is the frame again.
inline camera::Image BlockUpsampled(const camera::Image& image, int k) {
  camera::Image big = camera::Image::Rgb(k * image.width_px, k * image.height_px);
  for (int y = 0; y < big.height_px; ++y) {
    for (int x = 0; x < big.width_px; ++x) {
      for (int c = 0; c < 3; ++c) big.Row(y)[3 * x + c] = image.Row(y / k)[3 * (x / k) + c];
    }
  }
  return big;
}

// The shared real frames (not in the repository); tests skip when absent.
inline std::string SharedFrames() { return std::string(PATLAB_SOURCE_DIR) + "/../shared/frames"; }

// Whether the shared frames are there (their VSS test frame).
inline bool HaveSharedFrames() {
  return std::filesystem::exists(SharedFrames() + "/vss-test-frame.png");
}

}  // namespace patlab::vision::testing
