// stormlight render over a time series: several files and/or --times, numbered frames, a camera
// path from the scene's key frames, resumable, an MP4 through ffmpeg, frames across MPI ranks.
// Each frame is one ordinary `stormlight render` of one time, so a series frame and a single
// render of the same time are the same file.
#pragma once

#include "cli.h"

namespace sl {

// The options only a series has (declared on render's own parser).
void declare_series_options(Options &o);

// Renders the series when the command asks for one (several files, --times, --movie, a numbered
// --out pattern, or camera_keys in the scene) and returns the exit code; returns -1 for a single
// frame, which the caller renders itself. argv is what o parsed; render_frame is render's own
// single-frame entry point.
int render_series(Options &o, int argc, char **argv, int (*render_frame)(int argc, char **argv));

}  // namespace sl
