// stormlight render over a time series: several files and/or --times, numbered frames, a camera
// path from the scene's key frames, resumable, an MP4 through ffmpeg, frames across MPI ranks.
// Each frame is one ordinary `stormlight render` of one time, so a series frame and a single
// render of the same time are the same file.
#pragma once

#include "cli.h"
#include "render_session.h"

namespace sl {

// A frame's stages, seconds: what the series reports per frame and sets against its wall time.
struct FrameTimes {
  double load = 0;       // reading and resampling the storm
  double setup = 0;      // the air, the particle tables, the renderer (RenderSession::setup_seconds)
  double draw = 0;       // the volume and the sky behind it (RenderSession::draw): the skylight's
                         // lattice, the light and eye passes, the resolve, the background
  double composite = 0;  // VTK's compositing (and the fog's glow)
  double write = 0;
};

// What the frames of a series share, and what each reports back: VTK's compositing window
// (opened once for the series, not per frame) and the last frame's stage times.
struct FrameKeep {
  CompositeWindow window;
  FrameTimes times;
};

// The options only a series has (declared on render's own parser).
void declare_series_options(Options &o);

// Renders the series when the command asks for one (several files, --times, --movie, a numbered
// --out pattern, or camera_keys in the scene) and returns the exit code; returns -1 for a single
// frame, which the caller renders itself. argv is what o parsed; render_frame is render's own
// single-frame entry point, which fills keep->times and composites in keep->window.
int render_series(Options &o, int argc, char **argv, int (*render_frame)(int argc, char **argv, FrameKeep *keep));

}  // namespace sl
