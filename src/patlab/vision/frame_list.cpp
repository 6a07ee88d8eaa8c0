// The frame arguments of a command expanded to frame files (ExpandFrameList): folders, list files
// and single frames, each name checked to be UTF-8.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/frame_io_internal.h"

namespace patlab::vision {

namespace fs = std::filesystem;
using internal::HasExtension;

namespace {

// The frames a .txt/.list file names, one a line ('#' starts a comment), relative to its folder;
// a frame that does not exist is reported at its line.
void AppendListedFrames(const fs::path& path, const std::string& argument,
                        std::vector<std::string>* frames) {
  std::ifstream in(path);
  if (!in) throw InputError(argument + ": cannot open file; expected a readable list of frames");
  std::string line;
  int line_number = 0, listed = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    const size_t begin = line.find_first_not_of(" \t\r");
    if (begin == std::string::npos) continue;
    const size_t end = line.find_last_not_of(" \t\r");
    fs::path frame(line.substr(begin, end - begin + 1));
    if (frame.is_relative()) frame = path.parent_path() / frame;
    std::error_code ec;
    if (!fs::exists(frame, ec)) {
      throw InputError(FileLoc{argument, line_number},
                       "frame '" + EscapeForMessage(frame.string(), 1024) +
                           "' not found; expected a frame file, one a line");
    }
    frames->push_back(frame.string());
    ++listed;
  }
  if (listed == 0) {
    throw InputError(argument +
                     ": names no frame (empty, or only comments and blank lines); "
                     "expected one frame file a line");
  }
}

// Frame names go into UTF-8 CSV and JSON results: a name that is not UTF-8 is refused before the
// first frame, not by the JSON writer after the last.
void CheckUtf8Names(const std::vector<std::string>& frames) {
  for (const std::string& frame : frames) {
    if (!IsValidUtf8(frame)) {
      throw InputError(EscapeForMessage(frame, 1024) +
                       ": the file name is not valid UTF-8; expected UTF-8 file names (they go "
                       "into the results)");
    }
  }
}

}  // namespace

std::vector<std::string> ExpandFrameList(const std::vector<std::string>& arguments) {
  std::vector<std::string> frames;
  for (const std::string& argument : arguments) {
    const fs::path path(argument);
    std::error_code ec;  // a name the file system refuses (too long, a loop) is an InputError
    const bool exists = fs::exists(path, ec);
    ThrowIfPathUnusable(argument, ec);
    if (!exists)
      throw InputError(
          argument +
          ": no such file or directory; expected a frame, a directory of frames or a list file");
    if (fs::is_directory(path, ec)) {
      std::vector<std::string> found;
      fs::directory_iterator entries(path, ec);
      if (ec) {
        throw InputError(argument + ": cannot list the directory (" + ec.message() +
                         "); expected a readable directory of frames");
      }
      for (const auto& entry : entries) {
        if (entry.is_regular_file(ec) &&
            HasExtension(entry.path(),
                         {".png", ".jpg", ".jpeg", ".ppm", ".yuv", ".uyvy", ".raw"})) {
          found.push_back(entry.path().string());
        }
      }
      if (found.empty()) {
        throw InputError(argument +
                         ": no frames in directory; expected files ending in .png, .jpg, .jpeg, "
                         ".ppm, .yuv, .uyvy or .raw");
      }
      std::sort(found.begin(), found.end());
      frames.insert(frames.end(), found.begin(), found.end());
    } else if (HasExtension(path, {".txt", ".list"})) {
      AppendListedFrames(path, argument, &frames);
    } else {
      frames.push_back(argument);
    }
  }
  CheckUtf8Names(frames);
  return frames;
}

}  // namespace patlab::vision
