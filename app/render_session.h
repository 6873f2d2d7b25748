// What `stormlight render` prepares for a storm at one time, kept for many frames: plan once,
// draw many. The loaded frame, the air, the particle tables and the CPU renderer are built once;
// the GPU pass and VTK's compositing window are kept once opened. `render` draws one frame with
// it; `stormlight view` keeps it, so that a camera change costs one eye pass (and the sky for the
// new view), a sun change the light volume again, xi only the eye pass, and the exposure nothing
// here (the viewer re-tonemaps the kept HDR frame).
#pragma once

#include <memory>
#include <string>

#include "cli.h"
#include "gpu_render.h"
#include "sl_optics.h"
#include "sl_renderer.h"
#include "sl_scene_build.h"
#include "sl_sky.h"
#include "sl_storm.h"

namespace sl {

class TerrainScene;

// VTK's compositing window: the background, VTK's props (terrain, map layers) and the volume in a
// float framebuffer, the frame read back (alpha and depth are the volume's). Opened on its first
// frame and kept: a session's frames share it, and a series' (FrameKeep) all of theirs.
class CompositeWindow {
 public:
  CompositeWindow();
  ~CompositeWindow();
  CompositeWindow(const CompositeWindow &) = delete;
  CompositeWindow &operator=(const CompositeWindow &) = delete;
  bool composite(const sl_camera &cam, const sl_image &background, const sl_image &volume, sl_image *out,
                 const TerrainScene *terrain);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class RenderSession {
 public:
  RenderSession();
  ~RenderSession();
  RenderSession(const RenderSession &) = delete;
  RenderSession &operator=(const RenderSession &) = delete;

  // The scene of settings s (checked, sl_settings_check) through sl_scene_build: loads the storm
  // file at its time with the load options, places the sun (given angles, a date, or the file's
  // own time over the grid's centre), builds the air, the tables and the renderer. False with one
  // line; *exit is 2 for a usage error, 1 for a failure.
  bool prepare(const sl_settings &s, bool quiet, std::string *why, int *exit);
  // The volume is for the GPU pass (`view`, `render --gpu`): cloud and rain size tables then share
  // the fields it carries (SL_GPU_MAX_FIELDS, sl_load_options.max_fields).
  bool for_gpu = false;

  // Another sun (compass azimuth, elevation, degrees): the light volume is lit again on the next
  // frame, on the GPU or the CPU.
  bool set_sun(double elevation_deg, double compass_azimuth_deg, std::string *why);
  void set_xi(double xi);
  // The light-volume march's samples per grid cell (1..8) for the next draws; false with why.
  bool set_march_samples(int samples, std::string *why);

  // Frees the loaded fields once the renderer, the camera and the scene around the storm have read
  // them: the renderer draws from its own extinction grids, so a frame drawn once need not hold a
  // second copy of the storm through its passes and composite (on a 1000 x 1000 x 160 deck, half a
  // gigabyte). The frame keeps its grid, stats and columns; its fields are absent after.
  void release_fields();
  // Frees the renderer once the CPU has drawn the one frame: the composite, the glow and the write
  // read only the images, and the renderer's grids are the storm's size (on a 1000 x 1000 x 160
  // deck, half a gigabyte beside VTK's composite). Not after a GPU draw, whose drawer keeps it.
  // After it draw, set_sun and set_march_samples return false with a line.
  void release_renderer();

  // The volume layer and the background for cam. gpu: the GPU pass, falling back to the CPU
  // with *gpu_note saying why (then *gpu_done is false).
  bool draw(const sl_camera &cam, bool gpu, sl_image *volume, sl_image *background, sl_render_stats *stats,
            bool *gpu_done, std::string *gpu_note, std::string *why);
  // Composites background, VTK's props (terrain) and the volume in VTK's float framebuffer and
  // reads the frame back (alpha and depth are the volume's): in window where given (a series'
  // kept one), else in the session's own.
  bool composite(const sl_camera &cam, const sl_image &background, const sl_image &volume, sl_image *out,
                 const TerrainScene *terrain, CompositeWindow *window = nullptr);

  sl_settings settings{};  // what prepare read
  sl_built_scene built{};  // the storm, its sun, the air, the tables, the scene and the renderer
  sl_storm_frame &frame = built.frame;
  sl_scene &scene = built.scene;  // the renderer's scene: volume, air, tables, sun, xi
  sl_renderer *&renderer = built.renderer;
  double sun_elevation_deg = 0, sun_azimuth_deg = 0;  // compass
  std::string sun_note;                               // where the sun came from, when from a date
  double load_seconds = 0;
  double setup_seconds = 0;  // the rest of prepare: the air, the tables, the renderer

 private:
  struct Parts;
  std::unique_ptr<Parts> parts_;
};

// Writes a frame as render does: .exr linear HDR (half, or float) with the camera's matrices, the
// sun and the scene's text (when not empty) in its header; .png tone-mapped at `exposure`.
bool write_frame(const std::string &path, const sl_camera &cam, const sl_image &frame, const double sun_direction[3],
                 const std::string &scene_text, bool float_exr, float exposure, std::string *why);

}  // namespace sl
