// Movies from PNG frames through ffmpeg, run as a child process (H.264, yuv420p, MP4).
#pragma once

#include <string>
#include <vector>

namespace sl {

// Whether an ffmpeg executable is on PATH; fills error with a one-line way out when not.
bool ffmpeg_available(std::string *error);

// Encodes the PNG frames, in order, at fps frames per second into out (written to a temporary
// name and renamed when ffmpeg succeeded). Odd image sizes are padded by one pixel (H.264 4:2:0
// needs even sizes).
bool write_movie(const std::vector<std::string> &pngs, const std::string &out, double fps, std::string *error);

}  // namespace sl
