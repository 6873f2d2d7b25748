// stormlight render: a storm file to an HDR frame through a VTK render window.
#include <omp.h>
#include <vtkCamera.h>
#include <vtkNew.h>
#include <vtkRenderStepsPass.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"
#include "commands.h"
#include "composite_pass.h"
#include "render_session.h"
#include "render_series.h"
#include "gpu_render.h"
#include "night_scene.h"
#include "scene.h"
#include "terrain_scene.h"
#include "vtk_png.h"
#include <cjson/cJSON.h>
#ifndef SL_WITHOUT_APSF
#include "sl_aerosol.h"
#include "sl_glow.h"
#endif
#include "sl_image_io.h"
#include "sl_renderer.h"
#include "sl_optics.h"
#include "sl_sky.h"
#include "sl_geo.h"
#include "sl_storm.h"
#include "sl_tempfile.h"

namespace {

bool ends_with(const std::string &s, const std::string &suffix)
{
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

static int render_main(int argc, char **argv, sl::FrameKeep *keep = nullptr);

int sl_cmd_render(int argc, char **argv)
{
  // A scene file becomes arguments in front of the user's own, so flags override the file.
  std::vector<std::string> args;
  std::string scene_path;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--scene" && i + 1 < argc) scene_path = argv[++i];
    else if (a.rfind("--scene=", 0) == 0) scene_path = a.substr(8);
    else args.push_back(a);
  }
  if (scene_path.empty()) return render_main(argc, argv);
  std::vector<std::string> from_scene;
  std::string error;
  if (!sl::scene_to_arguments(scene_path, &from_scene, &error)) return sl::fail("render", error, 2);
  // The user's positional FILE replaces the scene's data.
  bool user_file = false;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i].rfind("--", 0) == 0) {
      if (i + 1 < args.size() && args[i + 1].rfind("--", 0) != 0) ++i;  // an option's value
      continue;
    }
    user_file = true;
  }
  if (user_file && !from_scene.empty() && from_scene[0].rfind("--", 0) != 0) from_scene.erase(from_scene.begin());
  std::vector<std::string> all = {"render"};
  all.insert(all.end(), from_scene.begin(), from_scene.end());
  all.insert(all.end(), args.begin(), args.end());
  all.push_back("--scene-text");
  all.push_back(scene_path);
  std::vector<char *> cargv;
  for (std::string &s : all) cargv.push_back(&s[0]);
  return render_main((int)cargv.size(), cargv.data());
}

static int render_main(int argc, char **argv, sl::FrameKeep *keep)
{
  sl::Options o("render", "FILE [FILE...] --out frame.exr[,frame.png] [options]",
                "Renders one time of a storm file with half-angle slicing (light buffer + eye buffer) and the\n"
                "multiple-scattering phase-function lighting of Riley et al. 2004 (or their low-albedo model),\n"
                "under the analytic sky with aerial perspective, composited with VTK's passes in a\n"
                "float framebuffer. EXR gets linear HDR RGBA (A = the volume's coverage) plus Z; PNG is\n"
                "tone-mapped sRGB. Without an X display VTK cannot open a window: run under 'xvfb-run -a'.");
  sl::declare_render_options(o);
  o.flag("cpu-composite", "composite on the CPU instead of through VTK (no X display needed)");
  o.flag("gpu", "draw the volume with the GPU pass (GLSL light sweep + ray-marched eye pass, docs/GPU.md);\n"
                "falls back to the CPU with a one-line note when the OpenGL context cannot");
  o.flag("quiet", "no progress bar or summary");
  o.flag("json", "print one JSON object: camera, sun direction, size, seconds");
  o.option("scene", "FILE.json", "read options from a scene file; command-line flags override it");
  o.option("scene-text", "FILE", "(internal) the scene file the options came from");
  sl::declare_series_options(o);
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  const int series_rc = sl::render_series(o, argc, argv, render_main);
  if (series_rc >= 0) return series_rc;
  const std::string cmd = "render";
  if (o.positional().size() != 1) return sl::fail(cmd, "give exactly one storm FILE", 2);
  const std::string path = o.positional()[0];
  if (!o.has("out")) return sl::fail(cmd, "missing --out FILE.exr or FILE.png", 2);

  std::vector<std::string> outs;
  {
    std::stringstream ss(o.str("out"));
    std::string item;
    while (std::getline(ss, item, ','))
      if (!item.empty()) outs.push_back(item);
  }
  sl_error err{};
  for (const std::string &f : outs) {
    if (!ends_with(f, ".exr") && !ends_with(f, ".png"))
      return sl::fail(cmd, f + ": output must end in .exr or .png", 2);
    char tmp[4096];
    if (sl_temp_name(f.c_str(), tmp, sizeof tmp, &err)) return sl::fail(cmd, err.message);
  }
  // The render options as typed settings (scene/sl_settings.h): the table's ranges and the
  // checks between options; RenderSession::prepare builds the scene from them.
  std::unique_ptr<sl_settings> settings(new sl_settings);
  {
    std::string why;
    if (!sl::settings_from_options(o, path, settings.get(), &why)) return sl::fail(cmd, why, 2);
    if (sl_settings_check(settings.get(), &err)) return sl::fail(cmd, err.message, 2);
  }
  // Overlay lines are rasterized by VTK, depth-tested against the terrain mesh; the CPU composite
  // has no line rasterizer, so it would silently drop them.
  if (o.has("cpu-composite"))
    for (const char *layer : {"coastlines", "borders", "graticule", "domain-outline", "scale-bar"})
      if (sl_settings_given(settings.get(), layer))
        return sl::fail(cmd,
                        std::string("--cpu-composite draws no overlay lines (--") + layer +
                            "): VTK draws them; composite through VTK (xvfb-run -a) or leave the overlays off",
                        2);
  const int threads = settings->threads;
  const long time_index = settings->time_index;
  const double exposure = settings->exposure, fog_km = settings->fog_visibility_km;
  const double fog_sky_km = settings->fog_depth_km;
  const bool haze = settings->fog_haze;
  if (!(fog_sky_km > 0)) return sl::fail(cmd, "--fog-depth-km must be > 0", 2);
  if (o.has("gpu") && settings->march_thin_depth > 0.0)
    return sl::fail(cmd, "--march-thin-depth is the CPU march's (--light-volume); the GPU pass takes every step", 2);
  if (o.has("gpu") && settings->march_refine_tolerance > 0.0)
    return sl::fail(cmd, "--march-refine is the CPU march's (--light-volume); the GPU pass marches every pixel", 2);
  if (threads > 0) omp_set_num_threads((int)threads);
  const bool json = o.has("json");
  const bool quiet = o.has("quiet") || json;

  // The storm, the sun, the air, the tables and the renderer (app/render_session.h).
  sl::RenderSession session;
  session.for_gpu = o.has("gpu");
  {
    std::string why;
    int exit_code = 1;
    if (!session.prepare(*settings, quiet, &why, &exit_code)) return sl::fail(cmd, why, exit_code);
  }
  const double t_load = session.load_seconds;
  const std::string &sun_note = session.sun_note;
  const sl_storm_frame &frame = session.frame;
  const sl_scene &scene = session.scene;
  double t0 = 0;
  sl_camera cam{};
  double lo_box[3], hi_box[3];
  sl_renderer_content_bounds(session.renderer, lo_box, hi_box);
  sl_scene_camera(&session.settings, &frame.volume, lo_box, hi_box, scene.sun_direction, &cam);
  // The scene around the storm: terrain (stops the eye rays, shadowed by the storm) and map layers.
  sl::MapLayers map_layers;
  std::unique_ptr<sl::TerrainScene> terrain;
  {
    std::string why;
    if (!sl::read_map_options(*settings, &map_layers, &why)) return sl::fail(cmd, why, 2);
    if (map_layers.any()) {
      terrain.reset(new sl::TerrainScene);
      if (!terrain->build(frame, map_layers, scene, &why) || !terrain->prepare_view(cam, &why))
        return sl::fail(cmd, path + ": " + why);
      cam.opaque_distance = terrain->opaque_distance();
    }
  }
  // Opaque per pixel: the terrain, and the round earth, which hides what lies beyond the horizon
  // (only with --curvature drop: the flat ground never cuts the volume). Also the frame's Z.
  std::vector<float> opaque((size_t)cam.width * cam.height, INFINITY);
  if (cam.opaque_distance) std::copy(cam.opaque_distance, cam.opaque_distance + opaque.size(), opaque.begin());
  if (sl_scene_ground_opaque(scene.atmosphere, &cam, opaque.data())) cam.opaque_distance = opaque.data();
  // Night: the stated night-sky luminance and the town's lamps (their eye rays stop at them).
  sl::NightScene night;
  {
    std::string why;
    if (!sl::read_night_scene(*settings, frame, &night, &why) || !sl::night_prepare_view(&night, &cam, &why))
      return sl::fail(cmd, why, 2);
  }
  // One frame from here on: the renderer holds the storm's extinction.
  session.release_fields();

  sl_image volume{}, background{}, frame_img{};
  int rc = 0;
  sl_render_stats stats{};
  double t_render = 0, t_composite = 0, t_write = 0;
  bool gpu_done = false;
  if (sl_image_alloc(&volume, cam.width, cam.height, &err) || sl_image_alloc(&background, cam.width, cam.height, &err) ||
      sl_image_alloc(&frame_img, cam.width, cam.height, &err)) {
    rc = sl::fail(cmd, err.message);
    goto done;
  }
  t0 = sl::now_seconds();
  {
    std::string why, gpu_note;
    if (!session.draw(cam, o.has("gpu"), &volume, &background, &stats, &gpu_done, &gpu_note, &why)) {
      rc = sl::fail(cmd, why);
      goto done;
    }
    if (o.has("gpu") && !gpu_done) std::fprintf(stderr, "render: --gpu: %s; rendering on the CPU\n", gpu_note.c_str());
  }
  if (!gpu_done) session.release_renderer();
  if ((night.night_sky[0] > 0.0 || night.night_sky[1] > 0.0 || night.night_sky[2] > 0.0) &&
      sl_night_sky_fill(&cam, night.night_sky, &background, &err)) {
    rc = sl::fail(cmd, err.message);
    goto done;
  }
  t_render = sl::now_seconds() - t0;
  t0 = sl::now_seconds();
  if (o.has("cpu-composite")) {
    if (terrain) terrain->paint_background(cam, background.rgba);
    sl_image_over(&volume, &background, &frame_img);
  } else {
    std::string display_error;
    if (!sl::have_display(&display_error)) {
      rc = sl::fail(cmd, display_error + " or pass --cpu-composite");
      goto done;
    }
    if (!session.composite(cam, background, volume, &frame_img, terrain.get(), keep ? &keep->window : nullptr)) {
      rc = sl::fail(cmd, "the VTK render window could not composite the frame (OpenGL float targets unavailable?)");
      goto done;
    }
  }
  // Z: the volume's opacity-weighted depth, then the terrain or ground behind what it lets through.
  sl_image_opaque_depth(&cam, opaque.data(), &background);
  sl_image_depth_over(&volume, &background, &frame_img);
  // The lamps through the volume renderer's transmittance to them (their rays stopped there).
  sl_point_lights_draw(night.pixels.data(), (int)night.pixels.size(), volume.transparency, &frame_img,
                       night.source_mask.empty() ? nullptr : night.source_mask.data());
#ifdef SL_WITHOUT_APSF
  if (fog_km > 0) {
    rc = sl::fail(cmd, "--fog-visibility-km needs the glow module (render/apsf), which this build left out", 2);
    goto done;
  }
#else
  if (fog_km > 0) {
    // Fog: small droplets, so the cloud tables' moments and albedos per channel (render/optics).
    // Haze: the rural aerosol through Mie, per channel q = g, W0 and extinction relative to 550 nm.
    // Extinction from the visibility by Koschmieder's 2 % contrast threshold (sl_aerosol.h).
    sl_optics_request req;
    sl_optics_request_defaults(&req);
    req.particles = 1u << SL_CLOUD;
    std::unique_ptr<sl_optics_tables, void (*)(sl_optics_tables *)> fog_tables(haze ? nullptr : sl_optics_build(&req, &err),
                                                                              sl_optics_free);
    if (!haze && !fog_tables) {
      rc = sl::fail(cmd, std::string("fog tables: ") + err.message);
      goto done;
    }
    sl_glow_params gp;
    sl_glow_params_defaults(&gp);
    sl_apsf_medium media[3];
    if (haze) {
      const double wavelengths[3] = {650.0, 515.0, 440.0};
      if (sl_glow_haze_media(wavelengths, media, gp.channel_sigma_scale, &err)) {
        rc = sl::fail(cmd, std::string("haze: ") + err.message);
        goto done;
      }
    }
    for (int c = 0; c < 3; ++c) {
      if (!haze) {
        const sl_phase_table *t = sl_optics_table(fog_tables.get(), SL_CLOUD, c);
        media[c] = sl_apsf_medium{t->albedo, t->moments[1], t->moments, t->n_moments};
      }
      gp.channel_medium[c] = &media[c];
    }
    gp.medium = media[1];
    gp.sigma = sl_koschmieder_extinction(fog_km * 1000.0);
    gp.sky_distance = fog_sky_km * 1000.0;
    /* A fog bank of that depth in front of the camera: farther things are seen through all of it. */
    gp.bank_depth = gp.sky_distance;
    gp.fov_y_deg = cam.fov_deg;
    gp.threshold = 1.0; /* radiance above the sun's irradiance per steradian: the sun's disk */
    if (!night.source_mask.empty()) gp.source_mask = night.source_mask.data(); /* and the lamps */
    // Eq. 31: the bank's airlight from the diffuse light of sky and ground (app/night_scene.h).
    std::vector<float> airlight_map;
    {
      std::string why;
      const sl_apsf_medium *const channel_media[3] = {&media[0], &media[1], &media[2]};
      if (!sl::fog_airlight(scene.atmosphere, scene.sun_direction, cam, night.night_sky,
                            channel_media, &airlight_map, &why)) {
        rc = sl::fail(cmd, why);
        goto done;
      }
      gp.airlight_map = airlight_map.data();
    }
    sl_glow_workspace *ws = sl_glow_workspace_create(cam.width, cam.height, 0, 0, &err);
    const int g = ws ? sl_glow_apply(ws, &gp, &frame_img, &frame_img, nullptr, &err) : 1;
    sl_glow_workspace_free(ws);
    if (g) {
      rc = sl::fail(cmd, std::string("fog glow: ") + err.message);
      goto done;
    }
  }
#endif
  t_composite = sl::now_seconds() - t0;
  t0 = sl::now_seconds();
  {
    std::string scene_text;
    if (o.has("scene-text")) {
      std::ifstream in(o.str("scene-text"));
      std::stringstream ss;
      ss << in.rdbuf();
      scene_text = ss.str();
    }
    for (const std::string &f : outs) {
      std::string why;
      if (!sl::write_frame(f, cam, frame_img, scene.sun_direction, scene_text, settings->float_exr, (float)exposure, &why)) {
        rc = sl::fail(cmd, why);
        goto done;
      }
    }
  }
  t_write = sl::now_seconds() - t0;
  if (keep) {
    keep->times.load = t_load, keep->times.setup = session.setup_seconds;
    keep->times.draw = t_render;
    keep->times.composite = t_composite;
    keep->times.write = t_write;
  }
  if (!quiet && !sun_note.empty()) std::printf("%s\n", sun_note.c_str());
  if (!quiet && terrain && !terrain->summary().empty()) std::printf("%s\n", terrain->summary().c_str());
  if (!quiet && stats.night) std::printf("night: the sun is below the horizon; this model gives no sunlight and no sky\n");
  if (!quiet && gpu_done)
    std::printf("rendered %s time %ld: %dx%d on the GPU pass; load %.3f s, light sweep %.3f s, eye pass %.3f s, "
                "composite %.3f s, write %.3f s\n",
                path.c_str(), time_index, cam.width, cam.height, t_load, stats.light_seconds, stats.eye_seconds,
                t_composite, t_write);
  if (!quiet && !gpu_done) {
    char sky_note[48] = "";
    if (stats.sky_seconds > 0) std::snprintf(sky_note, sizeof sky_note, "skylight %.3f s, ", stats.sky_seconds);
    std::printf("rendered %s time %ld: %dx%d, %d slices, light buffer %dx%d; load %.3f s, %slight pass %.3f s, eye "
                "pass %.3f s, composite %.3f s, write %.3f s\n",
                path.c_str(), time_index, cam.width, cam.height, stats.slices, stats.light_width,
                stats.light_height, t_load,
                sky_note, stats.light_seconds, stats.eye_seconds, t_composite, t_write);
  }
  if (json) {
    double fwd[3], right[3], up[3];
    sl_camera_basis(&cam, fwd, right, up);
    cJSON *root = cJSON_CreateObject();
    cJSON *c = cJSON_AddObjectToObject(root, "camera");
    cJSON_AddItemToObject(c, "position", cJSON_CreateDoubleArray(cam.position, 3));
    cJSON_AddItemToObject(c, "forward", cJSON_CreateDoubleArray(fwd, 3));
    cJSON_AddItemToObject(c, "up", cJSON_CreateDoubleArray(up, 3));
    cJSON_AddNumberToObject(c, "fov_y_deg", cam.fov_deg);
    cJSON_AddItemToObject(root, "sun_direction", cJSON_CreateDoubleArray(scene.sun_direction, 3));
    cJSON_AddNumberToObject(root, "width", cam.width);
    cJSON_AddNumberToObject(root, "height", cam.height);
    cJSON_AddNumberToObject(root, "seconds", t_load + t_render + t_composite + t_write);
    cJSON_AddNumberToObject(root, "slices", stats.slices);
    cJSON_AddBoolToObject(root, "night", stats.night != 0);
    char *text = cJSON_PrintUnformatted(root);
    std::printf("%s\n", text);
    std::free(text);
    cJSON_Delete(root);
  }
done:
  sl_image_free(&volume);
  sl_image_free(&background);
  sl_image_free(&frame_img);
  return rc;
}
