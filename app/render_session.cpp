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
#include "render_scene.h"
#include "sl_image_io.h"
#include "terrain_scene.h"
#include "vtk_png.h"

bool sl_parse_iso8601_utc(const std::string &text, sl_utc *out, std::string *why);  // cmd_sun.cpp

namespace sl {

namespace {

void progress_hook(void *user, double fraction) { static_cast<Progress *>(user)->update(fraction); }

}  // namespace

struct RenderSession::Parts {
  sl_atmosphere atmosphere{};
  std::unique_ptr<sl_optics_tables, void (*)(sl_optics_tables *)> optics{nullptr, sl_optics_free};
  std::unique_ptr<Progress> progress;
  GpuVolumeDrawer gpu;
  vtkSmartPointer<vtkRenderWindow> composite_window;
  vtkNew<vtkRenderer> composite_renderer;
  vtkNew<CompositePass> composite_pass;
  vtkNew<vtkRenderStepsPass> composite_steps;
};

RenderSession::RenderSession() : parts_(new Parts) {}

RenderSession::~RenderSession()
{
  parts_.reset();  // the GL resources first, while the renderer they were drawn from exists
  sl_renderer_destroy(renderer);
  if (have_frame_) sl_storm_frame_free(&frame);  // last: the renderer's scene pointed into it
}

bool RenderSession::prepare(const Options &opts, const std::string &path, bool quiet, std::string *why, int *exit)
{
  Options &o = const_cast<Options &>(opts);  // the accessors parse lazily
  const auto usage = [&](const std::string &message) {
    *why = message, *exit = 2;
    return false;
  };
  const auto failure = [&](const std::string &message) {
    *why = message, *exit = 1;
    return false;
  };
  long slices, light_res, time_index, march_samples;
  double dz;
  std::vector<double> sky;
  if (!o.integer("slices", &slices, 0, 16384) || !o.integer("light-resolution", &light_res, 0, 8192) ||
      !o.integer("march-samples", &march_samples, 1, 8) ||
      !o.integer("time", &time_index, 0, SL_MAX_TIMES - 1) || !o.number("dz", &dz) || !o.list("sky", &sky))
    return usage(o.error());
  if (sky.size() != 3) return usage("--sky needs three numbers R,G,B");
  if (o.has("sun-azimuth") != o.has("sun-elevation"))
    return usage("give both --sun-azimuth and --sun-elevation, or neither");
  if (o.has("sun-azimuth") && o.has("date")) return usage("give --date or the sun's angles, not both");
  double sun_az = 0, sun_el = 0;
  if (o.has("sun-azimuth")) {
    if (!o.number("sun-azimuth", &sun_az) || !o.number("sun-elevation", &sun_el)) return usage(o.error());
    if (sun_el < -90 || sun_el > 90) return usage("--sun-elevation must be in [-90, 90] degrees");
  }
  if (o.str("earth") != "flat" && o.str("earth") != "round") return usage("--earth must be flat or round");
  sl_lighting lighting;
  if (o.str("lighting") == "multiple") lighting = SL_LIGHTING_MULTIPLE;
  else if (o.str("lighting") == "eq25") lighting = SL_LIGHTING_MULTIPLE_EQ25;
  else if (o.str("lighting") == "low-albedo") lighting = SL_LIGHTING_LOW_ALBEDO;
  else return usage("--lighting must be multiple, eq25 or low-albedo");
  const bool spectral = o.str("wavelengths") == "spectral";
  if (!spectral && o.str("wavelengths") != "rgb") return usage("--wavelengths must be rgb or spectral");
  double xi;
  if (!o.number("xi", &xi) || xi < 0) return usage("--xi must be a number >= 0");
  if (spectral && o.has("no-atmosphere")) return usage("--wavelengths spectral needs the atmosphere");
  sl_utc date{};
  if (o.has("date") && !sl_parse_iso8601_utc(o.str("date"), &date, why)) return usage("--date: " + *why);

  double t0 = now_seconds();
  LoadOptions load;
  std::string load_error;
  if (!parse_load_options(o, &load, &load_error)) return usage(load_error);
  load.load.time_index = (int)time_index, load.load.dz = dz;
  if ((for_gpu || o.has("gpu")) && load.load.max_fields > SL_GPU_MAX_FIELDS) load.load.max_fields = SL_GPU_MAX_FIELDS;
  if (o.str("curvature") != "flat" && o.str("curvature") != "drop") return usage("--curvature must be flat or drop");
  load.load.earth_curvature = o.str("curvature") == "drop";
  if (o.has("origin")) {
    std::vector<double> origin;
    if (!o.list("origin", &origin) || origin.size() != 2 || !(std::fabs(origin[0]) <= 90.0))
      return usage("--origin needs LAT,LON in degrees");
    load.load.has_origin = 1, load.load.origin_lat = origin[0], load.load.origin_lon = origin[1];
  }
  sl_error err{};
  if (sl_storm_load(path.c_str(), &load.load, &frame, &err)) return failure(err.message);
  have_frame_ = true;
  load_seconds = now_seconds() - t0;

  // The sun: given angles, or the solar position for --date or the file's own time.
  if (!o.has("sun-azimuth")) {
    bool no_times = false;
    if (!frame_solar_position(path, time_index, frame, o.has("date") ? &date : nullptr, &sun_el, &sun_az, &date,
                              &no_times, why)) {
      *exit = no_times ? 2 : 1;
      return false;
    }
    char note[160];
    std::snprintf(note, sizeof note, "sun at %04d-%02d-%02d %02d:%02d UTC over %.2f N %.2f E: elevation %.2f, azimuth %.2f",
                  date.year, date.month, date.day, date.hour, date.minute, frame.center_lat, frame.center_lon, sun_el,
                  sun_az);
    sun_note = note;
  }
  const bool with_air = !o.has("no-atmosphere");
  double spectral_nm[SL_SKY_SPECTRAL_COUNT];
  sl_sky_spectral_wavelengths(spectral_nm);
  if (with_air && sl_atmosphere_init(&parts_->atmosphere, spectral ? spectral_nm : sl_sky_rgb_wavelengths_nm,
                                     spectral ? SL_SKY_SPECTRAL_COUNT : SL_SKY_RGB_COUNT,
                                     o.str("earth") == "flat" ? SL_EARTH_FLAT : SL_EARTH_ROUND,
                                     SL_RAYLEIGH_BODHAINE1999, &err))
    return failure(err.message);
  // The round earth the storm was placed on is also the ground the eye rays meet (the horizon).
  if (with_air && load.load.earth_curvature) parts_->atmosphere.ground_radius = SL_WRF_EARTH_RADIUS;

  // Particle tables only for the fields this storm has, at the scene's wavelengths (cached).
  if (lighting != SL_LIGHTING_LOW_ALBEDO) {
    sl_optics_request req;
    sl_optics_request_defaults(&req);
    sl_optics_request_fields(&req, &frame.volume);
    if (sl_optics_request_wavelengths(&req, spectral ? "spectral16" : "rgb", &err)) return failure(err.message);
    Progress table_progress("tables", !quiet);
    req.progress = progress_hook;
    req.progress_user = &table_progress;
    parts_->optics.reset(sl_optics_build(&req, &err));
    table_progress.done();
    if (!parts_->optics) return failure(std::string("particle tables: ") + err.message);
  }

  scene.volume = &frame.volume;
  scene.atmosphere = with_air ? &parts_->atmosphere : nullptr;
  scene.optics = parts_->optics.get();
  scene.lighting = lighting;
  scene.xi = xi;
  scene.light_volume = o.has("light-volume") ? 1 : 0;
  sun_elevation_deg = sun_el, sun_azimuth_deg = sun_az;
  // Compass azimuth into the volume's axes, which are the grid's (docs/GEOREFERENCING.md).
  sl_sun_direction(sun_el, sl_georef_grid_azimuth(&frame.georef, sun_az), scene.sun_direction);
  for (int c = 0; c < SL_CHANNELS; ++c) {
    scene.sun_irradiance[c] = 1.0;
    scene.sky_radiance[c] = sky[c];
  }
  scene.termination_transparency = 1e-6;
  scene.slices = (int)slices;
  scene.light_resolution = (int)light_res;
  scene.march_samples = (int)march_samples;
  parts_->progress.reset(new Progress("rendering", !quiet));
  scene.progress = progress_hook;
  scene.progress_user = parts_->progress.get();
  renderer = sl_renderer_create(&scene, &err);
  if (!renderer) return failure(path + ": " + err.message);
  return true;
}

bool RenderSession::set_sun(double elevation_deg, double compass_azimuth_deg, std::string *why)
{
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
  sl_renderer_set_xi(renderer, xi);
}

bool RenderSession::draw(const sl_camera &cam, bool gpu, sl_image *volume, sl_image *background,
                         sl_render_stats *stats, bool *gpu_done, std::string *gpu_note, std::string *why)
{
  *gpu_done = false;
  sl_error err{};
  if (gpu) {
    GpuTimings gt;
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
                              const TerrainScene *terrain)
{
  Parts &p = *parts_;
  if (!p.composite_window) {
    p.composite_window = offscreen_window(cam.width, cam.height);
    p.composite_window->AddRenderer(p.composite_renderer);
    p.composite_pass->SetDelegatePass(p.composite_steps);
    p.composite_renderer->SetPass(p.composite_pass);
    if (terrain) terrain->add_props(p.composite_renderer);
  } else {
    p.composite_window->SetSize(cam.width, cam.height);
  }
  vtkCamera *camera = p.composite_renderer->GetActiveCamera();
  camera->SetPosition(cam.position);
  camera->SetFocalPoint(cam.target);
  camera->SetViewUp(cam.up);
  camera->SetViewAngle(cam.fov_deg);
  double distance = 0.0;
  for (int a = 0; a < 3; ++a) distance += (cam.target[a] - cam.position[a]) * (cam.target[a] - cam.position[a]);
  distance = std::sqrt(distance);
  camera->SetClippingRange(std::max(1.0, 1e-3 * distance), 1e3 * distance);
  p.composite_pass->SetLayers(cam.width, cam.height, background.rgba, volume.rgba, volume.depth);
  p.composite_window->Render();
  const std::vector<float> &px = p.composite_pass->Result();
  if (!p.composite_pass->Succeeded() || px.size() != (size_t)cam.width * cam.height * 4) return false;
  for (size_t i = 0; i < px.size(); ++i) out->rgba[i] = px[i];
  for (size_t i = 0; i < (size_t)cam.width * cam.height; ++i) {
    out->rgba[4 * i + 3] = volume.rgba[4 * i + 3];
    out->depth[i] = volume.depth[i];
  }
  return true;
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
