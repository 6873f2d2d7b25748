// stormlight reference: the Monte Carlo reference. A scene file (JSON, docs/REFERENCE.md)
// names a storm to render, a medium given directly (for fluxes or an image), or a point source in
// an infinite medium; the path tracer in render/reference does the rest.
#include <cjson/cJSON.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"
#include "commands.h"
#include "scene.h"
#include "sl_georef.h"
#include "sl_image_io.h"
#include "sl_optics.h"
#include "sl_reference.h"
#include "sl_scene_build.h"
#include "sl_storm.h"

namespace {

const char *kCmd = "reference";
const double kPi = 3.14159265358979323846;

void progress_hook(void *user, double fraction) { static_cast<sl::Progress *>(user)->update(fraction); }

bool ends_with(const std::string &s, const std::string &tail)
{
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// A parse problem: the scene file's name goes in front of every message.
struct SceneError {
  std::string message;
};

std::string dir_of(const std::string &path)
{
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

std::string resolve(const std::string &scene_path, const std::string &p)
{
  return !p.empty() && p[0] == '/' ? p : dir_of(scene_path) + "/" + p;
}

const cJSON *member(const cJSON *obj, const char *key) { return obj ? cJSON_GetObjectItemCaseSensitive(obj, key) : nullptr; }

double number(const cJSON *obj, const char *key, double fallback, bool required = false)
{
  const cJSON *v = member(obj, key);
  if (!v) {
    if (required) throw SceneError{std::string("missing number \"") + key + "\""};
    return fallback;
  }
  if (!cJSON_IsNumber(v) || !std::isfinite(v->valuedouble))
    throw SceneError{std::string("\"") + key + "\" must be a finite number"};
  return v->valuedouble;
}

std::string text(const cJSON *obj, const char *key, const std::string &fallback)
{
  const cJSON *v = member(obj, key);
  if (!v) return fallback;
  if (!cJSON_IsString(v)) throw SceneError{std::string("\"") + key + "\" must be a string"};
  return v->valuestring;
}

bool boolean(const cJSON *obj, const char *key, bool fallback)
{
  const cJSON *v = member(obj, key);
  if (!v) return fallback;
  if (!cJSON_IsBool(v)) throw SceneError{std::string("\"") + key + "\" must be true or false"};
  return cJSON_IsTrue(v);
}

void numbers(const cJSON *obj, const char *key, int n, double *out, bool required)
{
  const cJSON *v = member(obj, key);
  if (!v) {
    if (required) throw SceneError{std::string("missing array \"") + key + "\""};
    return;
  }
  if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != n)
    throw SceneError{std::string("\"") + key + "\" must be an array of " + std::to_string(n) + " numbers"};
  for (int i = 0; i < n; ++i) {
    const cJSON *e = cJSON_GetArrayItem(v, i);
    if (!cJSON_IsNumber(e) || !std::isfinite(e->valuedouble))
      throw SceneError{std::string("\"") + key + "\" must hold finite numbers"};
    out[i] = e->valuedouble;
  }
}

// The sun: {"elevation_deg", "azimuth_deg"} or {"zenith_deg", "azimuth_deg"}; azimuth clockwise from north.
void sun_angles(const cJSON *root, double *zenith_deg, double *azimuth_deg)
{
  const cJSON *sun = member(root, "sun");
  if (!sun) throw SceneError{"missing \"sun\" {\"elevation_deg\" or \"zenith_deg\", \"azimuth_deg\"}"};
  if (member(sun, "zenith_deg")) *zenith_deg = number(sun, "zenith_deg", 0);
  else *zenith_deg = 90.0 - number(sun, "elevation_deg", 0, true);
  *azimuth_deg = number(sun, "azimuth_deg", 0);
  if (*zenith_deg < 0 || *zenith_deg > 180) throw SceneError{"the sun's zenith angle must lie in [0, 180] degrees"};
}

// Everything a scene file describes, owning what the C structures point to.
struct Scene {
  std::string kind;  // storm, medium, point
  std::vector<float> extinction;
  sl_storm_frame frame{};
  bool have_frame = false;
  std::unique_ptr<sl_optics_tables, void (*)(sl_optics_tables *)> optics{nullptr, sl_optics_free};
  sl_ref_medium *medium = nullptr;
  sl_atmosphere atmosphere{};
  bool with_air = false;
  double sky[3] = {0, 0, 0};  // without air: the constant sky (render's --sky)
  double sun_zenith = 0, sun_azimuth = 0;
  sl_camera camera{};
  bool have_camera = false;
  bool skylight = false;
  int max_scatter = 0;
  long photons = 100000;
  sl_ref_point_options point{};
  ~Scene()
  {
    sl_ref_medium_destroy(medium);
    if (have_frame) sl_storm_frame_free(&frame);
  }
};

void parse_camera(const cJSON *root, const sl_ref_medium *m, Scene *s)
{
  const cJSON *c = member(root, "camera");
  if (!c) return;
  const long width = (long)number(c, "width", 256), height = (long)number(c, "height", 256);
  if (width < 1 || height < 1 || width > 16384 || height > 16384) throw SceneError{"camera size out of range (1..16384)"};
  const double fov = number(c, "fov_deg", 40);
  if (member(c, "position")) {
    numbers(c, "position", 3, s->camera.position, true);
    numbers(c, "target", 3, s->camera.target, true);
    s->camera.up[2] = 1.0;
    numbers(c, "up", 3, s->camera.up, false);
    s->camera.fov_deg = fov, s->camera.width = (int)width, s->camera.height = (int)height;
  } else {
    // As `stormlight render`: framed on the content from a compass azimuth and an elevation.
    double lo[3], hi[3];
    sl_ref_medium_content_bounds(m, lo, hi);
    sl_camera_frame(lo, hi, number(c, "azimuth_deg", 200), number(c, "elevation_deg", 15), fov, (int)width,
                    (int)height, &s->camera);
  }
  s->have_camera = true;
}

void parse_medium(const cJSON *root, const std::string &path, Scene *s, sl_error *err)
{
  const cJSON *md = member(root, "medium");
  if (!md) throw SceneError{"missing \"medium\""};
  sl_ref_medium_desc d;
  sl_ref_medium_desc_defaults(&d);
  d.wavelength_nm[0] = number(root, "wavelength_nm", 550);
  const cJSON *ext = member(md, "extinction");
  double size[3] = {1, 1, 1};
  if (cJSON_IsNumber(ext)) {
    numbers(md, "size_m", 3, size, true);
    d.component[0].sigma[0] = ext->valuedouble;
    if (!(ext->valuedouble >= 0)) throw SceneError{"\"extinction\" must be >= 0 (1/m)"};
    for (int a = 0; a < 3; ++a) d.spacing[a] = size[a];
  } else if (cJSON_IsObject(ext)) {
    const std::string file = resolve(path, text(ext, "netcdf", ""));
    float *field = nullptr;
    sl_error read_err{};
    if (sl_read_field3d(file.c_str(), text(ext, "variable", "extinction").c_str(), d.n, &field, &read_err))
      throw SceneError{read_err.message};
    s->extinction.assign(field, field + (size_t)d.n[0] * d.n[1] * d.n[2]);
    std::free(field);
    numbers(md, "spacing_m", 3, d.spacing, true);
    d.component[0].sigma[0] = number(ext, "scale", 1.0);
    d.component[0].density = s->extinction.data();
    for (int a = 0; a < 3; ++a) size[a] = d.n[a] * d.spacing[a];
  } else {
    throw SceneError{"\"extinction\" must be a number (1/m) or {\"netcdf\": FILE, \"variable\": NAME}"};
  }
  for (int a = 0; a < 3; ++a)
    if (!(d.spacing[a] > 0)) throw SceneError{"grid spacing and sizes must be > 0"};
  // The box spans x, y symmetric about 0 and z from "bottom_m".
  const double bottom = number(md, "bottom_m", 0);
  d.origin[0] = -0.5 * size[0] + 0.5 * d.spacing[0];
  d.origin[1] = -0.5 * size[1] + 0.5 * d.spacing[1];
  d.origin[2] = bottom + 0.5 * d.spacing[2];
  d.component[0].albedo[0] = number(md, "albedo", 1.0);
  const cJSON *ph = member(md, "phase");
  const std::string type = text(ph, "type", "isotropic");
  if (type == "isotropic") d.component[0].phase[0].kind = SL_REF_PHASE_ISOTROPIC;
  else if (type == "hg") d.component[0].phase[0] = {SL_REF_PHASE_HG, number(ph, "g", 0, true), nullptr};
  else if (type == "rayleigh") d.component[0].phase[0].kind = SL_REF_PHASE_RAYLEIGH;
  else if (type == "particle") {
    const int p = sl_particle_from_name(text(ph, "particle", "").c_str());
    if (p < 0) throw SceneError{"phase \"particle\" must be cloud, rain, ice or snow"};
    sl_optics_request req;
    sl_optics_request_defaults(&req);
    req.particles = 1u << p;
    req.n_wavelengths = 1;
    req.wavelengths_nm[0] = d.wavelength_nm[0];
    s->optics.reset(sl_optics_build(&req, err));
    if (!s->optics) throw SceneError{std::string("particle tables: ") + err->message};
    d.component[0].phase[0] = {SL_REF_PHASE_TABLE, 0.0, sl_optics_table(s->optics.get(), (sl_particle)p, 0)};
  } else {
    throw SceneError{"phase \"type\" must be isotropic, hg, rayleigh or particle"};
  }
  const std::string lateral = text(md, "lateral", "periodic"), surface = text(md, "surface", "black");
  const std::string interp = text(md, "interpolation", "cell");
  if (lateral != "periodic" && lateral != "open") throw SceneError{"\"lateral\" must be periodic or open"};
  if (surface != "black" && surface != "none") throw SceneError{"\"surface\" must be black or none"};
  if (interp != "cell" && interp != "trilinear") throw SceneError{"\"interpolation\" must be cell or trilinear"};
  d.lateral = lateral == "periodic" ? SL_REF_PERIODIC : SL_REF_OPEN;
  d.black_surface = surface == "black";
  d.interpolation = interp == "cell" ? SL_REF_CELL : SL_REF_TRILINEAR;
  s->medium = sl_ref_medium_create(&d, err);
  if (!s->medium) throw SceneError{err->message};
  sun_angles(root, &s->sun_zenith, &s->sun_azimuth);
  const cJSON *fx = member(root, "fluxes");
  s->photons = (long)number(fx, "photons", 100000);
  parse_camera(root, s->medium, s);
}

void parse_storm(const cJSON *root, const std::string &path, Scene *s, sl_error *err, bool quiet)
{
  const std::string file = resolve(path, text(root, "storm", ""));
  if (text(root, "storm", "").empty()) throw SceneError{"missing \"storm\": a WRF file"};
  sl_load_options lo{};
  lo.time_index = (int)number(root, "time", 0);
  lo.dz = number(root, "dz_m", 0);
  if (sl_storm_load(file.c_str(), &lo, &s->frame, err)) throw SceneError{err->message};
  s->have_frame = true;
  const std::string wl = text(root, "wavelengths", "rgb");
  if (wl != "rgb" && wl != "spectral16") throw SceneError{"\"wavelengths\" must be rgb or spectral16"};
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  sl_optics_request_fields(&req, &s->frame.volume);
  if (sl_optics_request_wavelengths(&req, wl.c_str(), err)) throw SceneError{err->message};
  sl::Progress progress("tables", !quiet);
  req.progress = progress_hook;
  req.progress_user = &progress;
  s->optics.reset(sl_optics_build(&req, err));
  progress.done();
  if (!s->optics) throw SceneError{std::string("particle tables: ") + err->message};
  s->medium = sl_ref_medium_from_volume(&s->frame.volume, s->optics.get(), err);
  if (!s->medium) throw SceneError{err->message};
  const std::string earth = text(root, "earth", "round");
  if (earth != "round" && earth != "flat" && earth != "none") throw SceneError{"\"earth\" must be round, flat or none"};
  s->with_air = earth != "none";
  if (s->with_air) {
    std::vector<double> nm(sl_ref_medium_wavelength_count(s->medium));
    for (size_t w = 0; w < nm.size(); ++w) nm[w] = sl_ref_medium_wavelength(s->medium, (int)w);
    if (sl_atmosphere_init(&s->atmosphere, nm.data(), (int)nm.size(), earth == "flat" ? SL_EARTH_FLAT : SL_EARTH_ROUND,
                           SL_RAYLEIGH_BODHAINE1999, err))
      throw SceneError{err->message};
  }
  sun_angles(root, &s->sun_zenith, &s->sun_azimuth);
  s->skylight = boolean(root, "skylight", false);
  s->max_scatter = (int)number(root, "max_scatter", 0);
  if (!member(root, "camera")) throw SceneError{"missing \"camera\""};
  parse_camera(root, s->medium, s);
}

void parse_point(const cJSON *root, Scene *s)
{
  const cJSON *p = member(root, "point");
  if (!p) throw SceneError{"missing \"point\""};
  sl_ref_point_options_defaults(&s->point);
  s->point.optical_distance = number(p, "optical_distance", 0, true);
  s->point.albedo = number(p, "albedo", 1.0);
  s->point.g = number(p, "g", 0.0);
  s->point.bins = (int)number(p, "bins", 90);
  s->point.photons = (long)number(p, "photons", 100000);
}

// A `stormlight render` scene (docs/SCENES.md: a JSON object of render's options) read as render
// reads it (sl_settings_from_scene) and drawn by the reference with the storm, sun, air and camera
// render's sl_scene_build gives it, so that `validate` gives both renderers one scene. Render's own
// settings (lighting, slices, ...) are accepted and unused.
void parse_render_scene(const std::string &path, Scene *s, sl_error *err, bool quiet)
{
  std::unique_ptr<sl_settings> settings(new sl_settings);
  if (sl_settings_from_scene(settings.get(), path.c_str(), 0, nullptr, err)) {
    const std::string message = err->message, named = path + ": ";  // load_scene names the file
    throw SceneError{message.compare(0, named.size(), named) ? message : message.substr(named.size())};
  }
  sl::BuiltScenePtr built(new sl_built_scene{});
  if (sl_scene_load(settings.get(), 0, built.get(), err)) throw SceneError{err->message};
  s->frame = built->frame;  // the frame moves to the Scene, which frees it
  s->have_frame = true;
  built->have_frame = 0;
  // The sun's compass azimuth into the volume's axes, which are the grid's (docs/GEOREFERENCING.md).
  s->sun_zenith = 90.0 - built->sun_elevation_deg;
  s->sun_azimuth = sl_georef_grid_azimuth(&s->frame.georef, built->sun_azimuth_deg);
  const bool spectral = settings->spectral;
  sl::Progress progress("tables", !quiet);
  s->optics.reset(sl_scene_tables(&s->frame.volume, spectral, 0, progress_hook, &progress, err));
  progress.done();
  if (!s->optics) throw SceneError{std::string("particle tables: ") + err->message};
  s->medium = sl_ref_medium_from_volume(&s->frame.volume, s->optics.get(), err);
  if (!s->medium) throw SceneError{err->message};
  s->with_air = !settings->no_atmosphere;
  // The air as render's (sl_scene_air): its air mass, and the round ground under --curvature drop.
  if (s->with_air && sl_scene_air(settings.get(), spectral, &s->atmosphere, err)) throw SceneError{err->message};
  if (!s->with_air)
    for (int c = 0; c < 3; ++c) s->sky[c] = settings->sky[c];
  double lo[3], hi[3];
  sl_ref_medium_content_bounds(s->medium, lo, hi);
  double sun[3];
  sl_sun_direction(90.0 - s->sun_zenith, s->sun_azimuth, sun);
  sl_scene_camera(settings.get(), &s->frame.volume, lo, hi, sun, &s->camera);
  s->have_camera = true;
  s->kind = "storm";
}

bool load_scene(const std::string &path, Scene *s, std::string *why, bool quiet)
{
  std::ifstream in(path);
  if (!in) {
    *why = path + ": cannot open the scene file";
    return false;
  }
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string body = ss.str();
  std::unique_ptr<cJSON, void (*)(cJSON *)> root(cJSON_Parse(body.c_str()), cJSON_Delete);
  if (!root || !cJSON_IsObject(root.get())) {
    *why = path + ": not a JSON object";
    return false;
  }
  sl_error err{};
  try {
    s->kind = text(root.get(), "kind", "");
    if (s->kind.empty() && member(root.get(), "data")) parse_render_scene(path, s, &err, quiet);
    else if (s->kind == "medium") parse_medium(root.get(), path, s, &err);
    else if (s->kind == "storm") parse_storm(root.get(), path, s, &err, quiet);
    else if (s->kind == "point") parse_point(root.get(), s);
    else throw SceneError{"\"kind\" must be storm, medium or point"};
  } catch (const SceneError &e) {
    *why = path + ": " + e.message;
    return false;
  }
  return true;
}

int write_exr(const std::string &file, const sl_image &img, std::string *why, float exposure = 12.0f)
{
  sl_error err{};
  // A PNG (tone-mapped, for looking at) where the name asks for one; the reference itself is the EXR.
  const int status = ends_with(file, ".png") ? sl_write_png(file.c_str(), &img, exposure, &err)
                                             : sl_write_exr(file.c_str(), &img, SL_EXR_FLOAT, &err);
  if (status) {
    *why = err.message;
    return 1;
  }
  return 0;
}

void print_json(cJSON *root)
{
  char *t = cJSON_PrintUnformatted(root);
  std::printf("%s\n", t);
  std::free(t);
  cJSON_Delete(root);
}

}  // namespace

int sl_cmd_reference(int argc, char **argv)
{
  sl::Options o(kCmd,
                "--scene S.json [--spp N] [--seconds T] --out ref.exr [--stderr-out err.exr] [--json]\n"
                "   or: stormlight reference --scene medium.json --fluxes [--sun-zenith DEG] [--photons N] [--json]\n"
                "   or: stormlight reference --scene point.json [--photons N] [--json]",
                "Monte Carlo reference (docs/REFERENCE.md): a spectral volumetric path tracer on the same\n"
                "grid, particle tables, sun, sky and camera as `stormlight render`, so that the two differ\n"
                "only in how multiple scattering is treated. Scene kinds: \"storm\" (a WRF file and a camera:\n"
                "image), \"medium\" (extinction given directly: --fluxes gives domain-averaged reflectance,\n"
                "transmittance and absorptance with standard errors; with a camera, an image), \"point\"\n"
                "(a point source in an infinite medium: angular radiance at optical distance T). A scene of\n"
                "`stormlight render` (docs/SCENES.md, a \"data\" key and no \"kind\") is drawn with render's\n"
                "defaults: the same storm, sun, air and camera.\n"
                "Images: --out is the frame (volume layer over sky and sun), --stderr-out the standard error\n"
                "of each pixel's mean. Results are reproducible for a --seed and any number of threads.");
  o.option("scene", "FILE", "scene file (JSON; docs/REFERENCE.md)");
  o.option("spp", "N", "samples per pixel and wavelength", "64");
  o.option("seconds", "T", "stop after whole passes once T seconds have passed (0: no limit)", "0");
  o.option("out", "FILE.exr", "the reference frame (float EXR; .png: tone-mapped with exposure 12)");
  o.option("layer-out", "FILE.exr", "the volume layer alone (premultiplied, with transparency), as render/volume's");
  o.option("stderr-out", "FILE.exr", "per-pixel standard error of the frame's R, G, B");
  o.flag("fluxes", "medium scenes: reflectance, transmittance, absorptance of the collimated sun");
  o.option("sun-zenith", "DEG", "override the scene's sun zenith angle (fluxes)");
  o.option("photons", "N", "override the scene's photon count (fluxes, point)");
  o.option("seed", "N", "random seed", "1");
  o.option("threads", "N", "OpenMP threads (0: all)", "0");
  o.flag("json", "print one JSON object");
  o.flag("quiet", "no progress or summary lines");
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  if (!o.has("scene")) return sl::fail(kCmd, "--scene FILE is required", 2);
  long spp, seed, threads, photons = 0;
  double seconds;
  if (!o.integer("spp", &spp, 1, 100000000) || !o.integer("seed", &seed, 0, 0x7fffffffffffffffL) ||
      !o.integer("threads", &threads, 0, 4096) || !o.number("seconds", &seconds) ||
      (o.has("photons") && !o.integer("photons", &photons, 2, 1000000000000L)))
    return sl::fail(kCmd, o.error(), 2);
  if (seconds < 0) return sl::fail(kCmd, "--seconds must be >= 0", 2);
  if (threads > 0) omp_set_num_threads((int)threads);
  const bool quiet = o.has("quiet") || o.has("json");
  for (const char *f : {"out", "layer-out", "stderr-out"})
    if (o.has(f) && !ends_with(o.str(f), ".exr") && !ends_with(o.str(f), ".png"))
      return sl::fail(kCmd, o.str(f) + ": the file name must end in .exr (or .png, tone-mapped)", 2);

  Scene s;
  std::string why;
  const std::string path = o.str("scene");
  if (!load_scene(path, &s, &why, quiet)) return sl::fail(kCmd, why, 2);
  if (photons > 0) s.photons = photons, s.point.photons = photons;
  sl_error err{};

  if (s.kind == "point") {
    s.point.seed = (unsigned long long)seed;
    sl_ref_point_result r{};
    if (sl_ref_point_source(&s.point, &r, &err)) return sl::fail(kCmd, path + ": " + err.message);
    if (o.has("json")) {
      cJSON *root = cJSON_CreateObject();
      cJSON_AddNumberToObject(root, "optical_distance", s.point.optical_distance);
      cJSON_AddNumberToObject(root, "albedo", s.point.albedo);
      cJSON_AddNumberToObject(root, "g", s.point.g);
      cJSON_AddNumberToObject(root, "photons", (double)r.photons);
      cJSON_AddStringToObject(root, "normalisation",
                              "radiance per unit source power (I0 = 1/(4 pi)), sigma = 1; apsf = 16 pi^2 radiance "
                              "(render/apsf's S)");
      cJSON_AddNumberToObject(root, "direct_irradiance", r.direct_irradiance);
      cJSON_AddNumberToObject(root, "net_flux", r.net_flux);
      cJSON_AddNumberToObject(root, "se_net_flux", r.se_net_flux);
      auto arr = [&](const char *name, const double *v) {
        cJSON *a = cJSON_AddArrayToObject(root, name);
        for (int b = 0; b < r.bins; ++b) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[b]));
      };
      arr("theta_lo_deg", r.theta_lo_deg);
      arr("theta_hi_deg", r.theta_hi_deg);
      arr("radiance", r.radiance);
      arr("se_radiance", r.se_radiance);
      arr("apsf", r.apsf);
      arr("se_apsf", r.se_apsf);
      cJSON_AddNumberToObject(root, "seconds", r.seconds);
      print_json(root);
    } else {
      std::printf("point source, T = %g, albedo %g, g %g, %ld photons, %.2f s; net flux %.5f +- %.5f\n",
                  s.point.optical_distance, s.point.albedo, s.point.g, r.photons, r.seconds, r.net_flux, r.se_net_flux);
      std::printf("%10s %10s %14s %12s %14s\n", "theta_lo", "theta_hi", "radiance", "std.err", "apsf S");
      for (int b = 0; b < r.bins; ++b)
        std::printf("%10.3f %10.3f %14.6e %12.3e %14.6e\n", r.theta_lo_deg[b], r.theta_hi_deg[b], r.radiance[b],
                    r.se_radiance[b], r.apsf[b]);
    }
    sl_ref_point_result_free(&r);
    return 0;
  }

  if (o.has("fluxes")) {
    if (s.kind != "medium") return sl::fail(kCmd, path + ": --fluxes needs a scene of kind \"medium\"", 2);
    sl_ref_flux_options fo;
    sl_ref_flux_options_defaults(&fo);
    fo.sun_zenith_deg = s.sun_zenith;
    fo.sun_azimuth_deg = s.sun_azimuth;
    if (o.has("sun-zenith") && !o.number("sun-zenith", &fo.sun_zenith_deg)) return sl::fail(kCmd, o.error(), 2);
    fo.photons = s.photons;
    fo.seed = (unsigned long long)seed;
    sl_ref_fluxes_result r;
    if (sl_ref_fluxes(s.medium, &fo, &r, &err)) return sl::fail(kCmd, path + ": " + err.message, 2);
    if (o.has("json")) {
      cJSON *root = cJSON_CreateObject();
      cJSON_AddNumberToObject(root, "sun_zenith_deg", fo.sun_zenith_deg);
      cJSON_AddNumberToObject(root, "photons", (double)r.photons);
      cJSON_AddNumberToObject(root, "reflectance", r.reflectance);
      cJSON_AddNumberToObject(root, "transmittance", r.transmittance);
      cJSON_AddNumberToObject(root, "absorptance", r.absorptance);
      cJSON_AddNumberToObject(root, "side", r.side);
      cJSON_AddNumberToObject(root, "direct_transmittance", r.direct_transmittance);
      cJSON_AddNumberToObject(root, "se_reflectance", r.se_reflectance);
      cJSON_AddNumberToObject(root, "se_transmittance", r.se_transmittance);
      cJSON_AddNumberToObject(root, "se_absorptance", r.se_absorptance);
      cJSON_AddNumberToObject(root, "se_side", r.se_side);
      cJSON_AddNumberToObject(root, "mean_scatterings", r.mean_scatterings);
      cJSON_AddNumberToObject(root, "seconds", r.seconds);
      print_json(root);
    } else {
      std::printf("sun zenith %g deg, %ld photons, %.2f s, %.1f scatterings per photon\n", fo.sun_zenith_deg,
                  r.photons, r.seconds, r.mean_scatterings);
      std::printf("reflectance   %.6f +- %.6f\ntransmittance %.6f +- %.6f (direct %.6f)\nabsorptance   %.6f +- %.6f\n",
                  r.reflectance, r.se_reflectance, r.transmittance, r.se_transmittance, r.direct_transmittance,
                  r.absorptance, r.se_absorptance);
      if (r.side > 0) std::printf("side          %.6f +- %.6f\n", r.side, r.se_side);
    }
    return 0;
  }

  if (!s.have_camera) return sl::fail(kCmd, path + ": an image needs a \"camera\" (or use --fluxes)", 2);
  if (!o.has("out") && !o.has("layer-out") && !o.has("json"))
    return sl::fail(kCmd, "give --out FILE.exr (and/or --layer-out, --json)", 2);
  sl_ref_scene sc;
  sl_ref_scene_defaults(&sc);
  sc.medium = s.medium;
  sl_sun_direction(90.0 - s.sun_zenith, s.sun_azimuth, sc.sun_direction);
  sc.atmosphere = s.with_air ? &s.atmosphere : nullptr;
  for (int c = 0; c < 3; ++c) sc.sky_radiance[c] = s.sky[c];
  sc.skylight = s.skylight;
  sc.max_scatter = s.max_scatter;
  sc.seed = (unsigned long long)seed;
  // Eye rays stop at the round ground under --curvature drop, as render's and validate's do.
  sl_camera cam = s.camera;
  std::vector<float> ground((size_t)cam.width * cam.height, INFINITY);
  if (sl_scene_ground_opaque(sc.atmosphere, &cam, ground.data())) cam.opaque_distance = ground.data();
  sl_ref_accum acc{};
  sl_image layer{}, background{}, frame{}, se_img{};
  std::vector<float> se((size_t)cam.width * cam.height * 3);
  int rc = 0;
  if (sl_ref_accum_init(&acc, cam.width, cam.height, sl_ref_medium_wavelength_count(s.medium), &err) ||
      sl_image_alloc(&layer, cam.width, cam.height, &err) || sl_image_alloc(&background, cam.width, cam.height, &err) ||
      sl_image_alloc(&frame, cam.width, cam.height, &err) || sl_image_alloc(&se_img, cam.width, cam.height, &err)) {
    rc = sl::fail(kCmd, err.message);
  } else {
    sl::Progress progress("reference", !quiet);
    sl_ref_budget budget{spp, seconds, progress_hook, &progress};
    if (sl_ref_render(&sc, &cam, &budget, &acc, &err) || sl_ref_accum_image(&acc, s.medium, &layer, se.data(), &err) ||
        sl_ref_background(&sc, &cam, &background, &err)) {
      rc = sl::fail(kCmd, path + ": " + err.message);
    } else {
      progress.done();
      sl_image_over(&layer, &background, &frame);
      double se2 = 0, v2 = 0;
      for (size_t q = 0; q < (size_t)cam.width * cam.height; ++q) {
        for (int c = 0; c < 3; ++c) {
          se_img.rgba[4 * q + c] = se[3 * q + c];
          se2 += (double)se[3 * q + c] * se[3 * q + c];
          v2 += (double)frame.rgba[4 * q + c] * frame.rgba[4 * q + c];
        }
        se_img.rgba[4 * q + 3] = 1.0f;
        se_img.depth[q] = INFINITY;
        se_img.transparency[q] = 0.0f;
      }
      const double noise = v2 > 0 ? std::sqrt(se2 / v2) : 0.0;
      if ((o.has("out") && write_exr(o.str("out"), frame, &why)) ||
          (o.has("layer-out") && write_exr(o.str("layer-out"), layer, &why)) ||
          (o.has("stderr-out") && write_exr(o.str("stderr-out"), se_img, &why))) {
        rc = sl::fail(kCmd, why);
      } else if (o.has("json")) {
        cJSON *root = cJSON_CreateObject();
        cJSON_AddStringToObject(root, "scene", path.c_str());
        cJSON_AddNumberToObject(root, "width", cam.width);
        cJSON_AddNumberToObject(root, "height", cam.height);
        cJSON_AddNumberToObject(root, "wavelengths", sl_ref_medium_wavelength_count(s.medium));
        cJSON_AddNumberToObject(root, "spp", (double)acc.samples);
        cJSON_AddNumberToObject(root, "seconds", acc.seconds);
        cJSON_AddNumberToObject(root, "relative_noise", noise);
        cJSON_AddNumberToObject(root, "seed", (double)seed);
        print_json(root);
      } else if (!quiet) {
        std::printf("reference %s: %dx%d, %ld samples per pixel and wavelength, %.2f s, relative noise (RMS standard "
                    "error / RMS radiance) %.4f\n",
                    path.c_str(), cam.width, cam.height, acc.samples, acc.seconds, noise);
      }
    }
  }
  sl_ref_accum_free(&acc);
  sl_image_free(&layer);
  sl_image_free(&background);
  sl_image_free(&frame);
  sl_image_free(&se_img);
  return rc;
}
