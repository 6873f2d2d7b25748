#include "render_session.h"

#include <vtkCamera.h>
#include <vtkNew.h>
#include <vtkRenderStepsPass.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "composite_pass.h"
#include "scene.h"
#include "sl_image_io.h"
#include "terrain_scene.h"
#include "vtk_png.h"

namespace sl {

namespace {

void progress_hook(void *user, double fraction) { static_cast<Progress *>(user)->update(fraction); }

}  // namespace

struct CompositeWindow::Impl {
  vtkSmartPointer<vtkRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<CompositePass> pass;
  vtkNew<vtkRenderStepsPass> steps;
};

CompositeWindow::CompositeWindow() : impl_(new Impl) {}
CompositeWindow::~CompositeWindow() = default;

bool CompositeWindow::composite(const sl_camera &cam, const sl_image &background, const sl_image &volume,
                                sl_image *out, const TerrainScene *terrain)
{
  Impl &p = *impl_;
  if (!p.window) {
    p.window = offscreen_window(cam.width, cam.height);
    p.window->AddRenderer(p.renderer);
    p.pass->SetDelegatePass(p.steps);
    p.renderer->SetPass(p.pass);
  } else {
    p.window->SetSize(cam.width, cam.height);
  }
  // This frame's props: the last frame's terrain (another time of a series) is not this one's.
  p.renderer->RemoveAllViewProps();
  if (terrain) terrain->add_props(p.renderer);
  vtkCamera *camera = p.renderer->GetActiveCamera();
  camera->SetPosition(cam.position);
  camera->SetFocalPoint(cam.target);
  camera->SetViewUp(cam.up);
  camera->SetViewAngle(cam.fov_deg);
  double distance = 0.0;
  for (int a = 0; a < 3; ++a) distance += (cam.target[a] - cam.position[a]) * (cam.target[a] - cam.position[a]);
  distance = std::sqrt(distance);
  camera->SetClippingRange(std::max(1.0, 1e-3 * distance), 1e3 * distance);
  p.pass->SetLayers(cam.width, cam.height, background.rgba, volume.rgba, volume.depth);
  p.window->Render();
  const std::vector<float> &px = p.pass->Result();
  if (!p.pass->Succeeded() || px.size() != (size_t)cam.width * cam.height * 4) return false;
  for (size_t i = 0; i < px.size(); ++i) out->rgba[i] = px[i];
  for (size_t i = 0; i < (size_t)cam.width * cam.height; ++i) {
    out->rgba[4 * i + 3] = volume.rgba[4 * i + 3];
    out->depth[i] = volume.depth[i];
  }
  return true;
}

struct RenderSession::Parts {
  std::unique_ptr<Progress> progress;
  GpuVolumeDrawer gpu;
  CompositeWindow window;
};

RenderSession::RenderSession() : parts_(new Parts) {}

RenderSession::~RenderSession()
{
  // The GL resources first, while the renderer they were drawn from exists (a CPU draw after a
  // failed GPU one has released it: their release reads only textures and framebuffers).
  parts_.reset();
  sl_built_scene_free(&built);
}

bool RenderSession::prepare(const sl_settings &s, bool quiet, std::string *why, int *exit)
{
  settings = s;
  sl_error err{};
  Progress table_progress("tables", !quiet);
  parts_->progress.reset(new Progress("rendering", !quiet));
  sl_build_options build{};
  build.for_gpu = for_gpu;
  build.tables_progress = progress_hook, build.tables_progress_user = &table_progress;
  build.render_progress = progress_hook, build.render_progress_user = parts_->progress.get();
  const double t0 = now_seconds();
  const int rc = sl_scene_build(&settings, &build, &built, &err);
  table_progress.done();
  if (rc) {
    *why = err.message, *exit = rc == SL_ERR_ARG ? 2 : 1;
    return false;
  }
  load_seconds = built.load_seconds;
  setup_seconds = now_seconds() - t0 - load_seconds;
  sun_elevation_deg = built.sun_elevation_deg, sun_azimuth_deg = built.sun_azimuth_deg;
  if (built.sun_from_time) {
    const sl_utc &d = built.sun_time;
    char note[160];
    std::snprintf(note, sizeof note, "sun at %04d-%02d-%02d %02d:%02d UTC over %.2f N %.2f E: elevation %.2f, azimuth %.2f",
                  d.year, d.month, d.day, d.hour, d.minute, frame.center_lat, frame.center_lon, sun_elevation_deg,
                  sun_azimuth_deg);
    sun_note = note;
  }
  return true;
}

void RenderSession::release_fields()
{
  for (int k = 0; k < SL_VOLUME_SLOTS; ++k) sl_volume_drop_field(&built.frame.volume, k);
}

void RenderSession::release_renderer()
{
  sl_renderer_destroy(renderer);
  renderer = nullptr;
}

// After release_renderer nothing may draw or change the light: a caller that tries gets a line, not
// a null renderer.
static bool renderer_kept(const sl_renderer *renderer, std::string *why)
{
  if (renderer) return true;
  *why = "the renderer was freed after its one frame";
  return false;
}

bool RenderSession::set_sun(double elevation_deg, double compass_azimuth_deg, std::string *why)
{
  if (!renderer_kept(renderer, why)) return false;
  double sun[3];
  sl_sun_direction(elevation_deg, sl_georef_grid_azimuth(&frame.georef, compass_azimuth_deg), sun);
  sl_error err{};
  if (sl_renderer_set_sun(renderer, sun, &err)) {
    *why = err.message;
    return false;
  }
  for (int a = 0; a < 3; ++a) scene.sun_direction[a] = sun[a];
  sun_elevation_deg = elevation_deg, sun_azimuth_deg = compass_azimuth_deg;
  parts_->gpu.resweep();
  return true;
}

bool RenderSession::set_march_samples(int samples, std::string *why)
{
  if (!renderer_kept(renderer, why)) return false;
  sl_error err{};
  if (sl_renderer_set_march_samples(renderer, samples, &err)) {
    *why = err.message;
    return false;
  }
  scene.march_samples = samples;
  return true;
}

void RenderSession::set_xi(double xi)
{
  scene.xi = xi;
  if (renderer) sl_renderer_set_xi(renderer, xi);
}

bool RenderSession::draw(const sl_camera &cam, bool gpu, sl_image *volume, sl_image *background,
                         sl_render_stats *stats, bool *gpu_done, std::string *gpu_note, std::string *why)
{
  *gpu_done = false;
  if (!renderer_kept(renderer, why)) return false;
  sl_error err{};
  if (gpu) {
    GpuTimings gt;
    if (sl_renderer_prepare_sky(renderer, nullptr, &err)) {
      *why = err.message;
      return false;
    }
    if (!have_display(gpu_note)) {
    } else if (parts_->gpu.draw(renderer, cam, volume, background, gpu_note, &gt)) {
      *stats = sl_render_stats{};
      stats->light_seconds = gt.light_seconds, stats->eye_seconds = gt.eye_seconds;
      *gpu_done = true;
    }
  }
  // The CPU draws what the GPU did not: the whole frame, the volume and the sky.
  if (!*gpu_done && (sl_renderer_render(renderer, &cam, volume, stats, &err) ||
                     sl_renderer_background(renderer, &cam, background, &err))) {
    *why = err.message;
    return false;
  }
  if (parts_->progress) parts_->progress->done();
  return true;
}

bool RenderSession::composite(const sl_camera &cam, const sl_image &background, const sl_image &volume, sl_image *out,
                              const TerrainScene *terrain, CompositeWindow *window)
{
  return (window ? window : &parts_->window)->composite(cam, background, volume, out, terrain);
}

bool write_frame(const std::string &path, const sl_camera &cam, const sl_image &frame, const double sun_direction[3],
                 const std::string &scene_text, bool float_exr, float exposure, std::string *why)
{
  sl_exr_metadata meta{};
  double distance = 0.0;
  for (int a = 0; a < 3; ++a) distance += (cam.target[a] - cam.position[a]) * (cam.target[a] - cam.position[a]);
  sl_exr_camera_matrices(cam.position, cam.target, cam.up, cam.fov_deg, (double)cam.width / cam.height,
                         std::max(1.0, 1e-3 * std::sqrt(distance)), 1e3 * std::sqrt(distance), &meta);
  meta.has_sun = 1;
  for (int a = 0; a < 3; ++a) meta.sun_direction[a] = (float)sun_direction[a];
  if (!scene_text.empty()) meta.scene = scene_text.c_str();
  const bool exr = path.size() >= 4 && path.compare(path.size() - 4, 4, ".exr") == 0;
  sl_error err{};
  const int w = exr ? sl_write_exr_meta(path.c_str(), &frame, float_exr ? SL_EXR_FLOAT : SL_EXR_HALF, &meta, &err)
                    : sl_write_png(path.c_str(), &frame, exposure, &err);
  if (w) *why = err.message;
  return w == 0;
}

}  // namespace sl
