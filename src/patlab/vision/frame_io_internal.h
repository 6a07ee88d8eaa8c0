// Pieces of frame reading shared by frame_io.cpp (decoding and writing frames) and frame_list.cpp
// (the frame arguments of a command expanded to frame files). Not part of the public API: include
// frame_io.h instead.
#pragma once

#include <filesystem>
#include <initializer_list>

namespace patlab::vision::internal {

// Whether the path's extension, in lower case, is one of `extensions` (".png", ...).
bool HasExtension(const std::filesystem::path& path, std::initializer_list<const char*> extensions);

}  // namespace patlab::vision::internal
