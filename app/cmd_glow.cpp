// stormlight glow: glows around the light sources of an HDR frame by depth-dependent convolution
// with the Narasimhan et al. point spread function, plus attenuation and airlight (eqs. 30-31).
// Works on the EXR frames of 'stormlight render' (Z = view-axis distance, +inf for the sky).
// Computes nothing itself: everything comes from render/apsf.
#include <cjson/cJSON.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cli.h"
#include "commands.h"
#include "sl_aerosol.h"
#include "sl_glow.h"
#include "sl_image_io.h"
#include "sl_optics.h"

namespace {

const char *kCmd = "glow";

bool ends_with(const std::string &s, const std::string &suffix)
{
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void progress_hook(void *user, double fraction) { static_cast<sl::Progress *>(user)->update(fraction); }

}  // namespace

int sl_cmd_glow(int argc, char **argv)
{
  sl::Options o(kCmd, "IN.exr --out OUT.exr|OUT.png [--visibility-km V | --T T] [--q Q] [options]",
                "Adds glows around light sources (pixels whose largest RGB value reaches --threshold) by a\n"
                "depth-dependent convolution with the atmospheric PSF (Narasimhan et al., sections 7.2-7.3), and\n"
                "attenuates the rest (eq. 30) with optional airlight (eq. 31). The depth comes from the EXR's Z\n"
                "channel (distance along the view axis, as 'stormlight render' writes it); T = sigma * distance\n"
                "with sigma = 3.912 / visibility (Koschmieder). Pixels of infinite depth (the sky) are outside\n"
                "the fog unless --sky-distance-km gives them a distance; with --T every pixel is at that T.");
  o.option("out", "FILE", "output: .exr (linear HDR, float) or .png (tone mapped)");
  o.option("visibility-km", "V", "meteorological visibility of the haze or fog in km (sets sigma)");
  o.option("T", "T", "one optical thickness for every pixel instead of depth (> 0)");
  o.option("q", "Q", "Henyey-Greenstein parameter of the particles, (-1, 1)", "0.9");
  o.option("albedo", "W0", "single-scattering albedo, (0, 1]", "1");
  o.option("particle", "NAME", "instead of --q/--albedo: render/optics tables of cloud, rain, ice or snow at 650, 515, "
           "440 nm for red, green, blue");
  o.option("medium", "haze|fog", "instead of --q/--albedo/--particle: haze (Shettle & Fenn's rural aerosol through Mie:\n"
           "q = g, W0 and extinction per channel, sigma at 550 nm) or fog (cloud-droplet tables)");
  o.option("depth-channel", "NAME", "EXR channel holding the view-axis distance (only Z is read)", "Z");
  o.option("fov", "DEG", "vertical field of view of the camera that made the frame", "40");
  o.option("threshold", "L", "a pixel is a light source when its largest RGB value reaches L", "1");
  o.option("layers", "N", "at most N depth layers, evenly spaced in log T over the sources, >= 2 % apart (1..64)", "8");
  o.option("sky-distance-km", "D", "distance given to pixels of infinite depth (default: no fog in front of the sky)");
  o.option("airlight", "R,G,B", "horizon radiance L_sky of eq. 31 added as L_sky (1 - e^-T)", "0,0,0");
  o.option("normalisation", "N", "fluence (physical, resolution independent) or peak (the source pixel keeps its value)",
           "fluence");
  o.option("tolerance", "E", "series truncation error as a fraction of the PSF's forward value", "1e-4");
  o.option("exposure", "E", "PNG tone mapping: 1 - exp(-E L)", "12");
  o.flag("no-attenuation", "leave pixels that are not sources as they are (glows only)");
  o.flag("json", "print one JSON object with the layers and timings");
  o.flag("quiet", "no progress bar or summary");
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  if (o.positional().size() != 1) return sl::fail(kCmd, "give exactly one input IN.exr", 2);
  const std::string in_path = o.positional()[0];
  if (!o.has("out")) return sl::fail(kCmd, "missing --out OUT.exr or OUT.png", 2);
  const std::string out_path = o.str("out");
  const bool png = ends_with(out_path, ".png");
  if (!png && !ends_with(out_path, ".exr")) return sl::fail(kCmd, "--out must end in .exr or .png: " + out_path, 2);
  if (o.str("depth-channel") != "Z")
    return sl::fail(kCmd, "--depth-channel: only Z is read (the channel 'stormlight render' writes)", 2);
  if (o.has("visibility-km") && o.has("T")) return sl::fail(kCmd, "give --visibility-km or --T, not both", 2);
  if (!o.has("visibility-km") && !o.has("T")) return sl::fail(kCmd, "give --visibility-km V or --T T", 2);

  sl_glow_params p;
  sl_glow_params_defaults(&p);
  double visibility = 0, fov, threshold, tolerance, exposure, sky_km = 0;
  long layers;
  std::vector<double> airlight;
  if ((o.has("visibility-km") && !o.number("visibility-km", &visibility)) || (o.has("T") && !o.number("T", &p.fixed_T)) ||
      !o.number("q", &p.medium.q) || !o.number("albedo", &p.medium.albedo) || !o.number("fov", &fov) ||
      !o.number("threshold", &threshold) || !o.integer("layers", &layers, 1, SL_GLOW_MAX_LAYERS) ||
      !o.number("tolerance", &tolerance) || !o.number("exposure", &exposure) || !o.list("airlight", &airlight) ||
      (o.has("sky-distance-km") && !o.number("sky-distance-km", &sky_km)))
    return sl::fail(kCmd, o.error(), 2);
  if (o.has("visibility-km") && !(visibility > 0 && std::isfinite(visibility)))
    return sl::fail(kCmd, "--visibility-km must be > 0", 2);
  if (o.has("T") && !(p.fixed_T > 0 && std::isfinite(p.fixed_T))) return sl::fail(kCmd, "--T must be > 0", 2);
  if (!(p.medium.q > -1 && p.medium.q < 1)) return sl::fail(kCmd, "--q must be in (-1, 1)", 2);
  if (!(p.medium.albedo > 0 && p.medium.albedo <= 1)) return sl::fail(kCmd, "--albedo must be in (0, 1]", 2);
  if (!(fov > 0 && fov < 170)) return sl::fail(kCmd, "--fov must be in (0, 170) degrees", 2);
  if (!(threshold > 0)) return sl::fail(kCmd, "--threshold must be > 0", 2);
  if (!(tolerance > 0 && tolerance < 0.1)) return sl::fail(kCmd, "--tolerance must be in (0, 0.1)", 2);
  if (airlight.size() != 3 || airlight[0] < 0 || airlight[1] < 0 || airlight[2] < 0)
    return sl::fail(kCmd, "--airlight needs three values R,G,B >= 0", 2);
  if (o.has("sky-distance-km") && !(sky_km > 0 && std::isfinite(sky_km)))
    return sl::fail(kCmd, "--sky-distance-km must be > 0", 2);
  const std::string norm = o.str("normalisation");
  if (norm != "fluence" && norm != "peak") return sl::fail(kCmd, "--normalisation must be fluence or peak", 2);
  if (o.has("visibility-km")) p.sigma = sl_koschmieder_extinction(visibility * 1000.0); /* 2 % contrast */
  p.sky_distance = sky_km * 1000.0;
  p.fov_y_deg = fov;
  p.threshold = threshold;
  p.n_layers = (int)layers;
  p.tolerance = tolerance;
  p.norm = norm == "peak" ? SL_GLOW_PEAK : SL_GLOW_FLUENCE;
  p.attenuate = !o.has("no-attenuation");
  for (int c = 0; c < 3; ++c) p.airlight[c] = airlight[c];

  sl_error err{};
  // With --particle the three channels get the tables' moments and albedos (render/optics);
  // --medium fog is --particle cloud, --medium haze the aerosol model (not grey: per-channel sigma).
  sl_optics_tables *tables = nullptr;
  sl_apsf_medium media[3];
  std::string particle = o.has("particle") ? o.str("particle") : "";
  if (o.has("medium")) {
    if (o.has("particle") || o.has("q") || o.has("albedo"))
      return sl::fail(kCmd, "--medium sets the particles: give it without --particle, --q or --albedo", 2);
    const std::string medium = o.str("medium");
    if (medium == "fog") {
      particle = "cloud";
    } else if (medium == "haze") {
      const double wavelengths[3] = {650.0, 515.0, 440.0};
      if (sl_glow_haze_media(wavelengths, media, p.channel_sigma_scale, &err)) return sl::fail(kCmd, err.message);
      for (int c = 0; c < 3; ++c) p.channel_medium[c] = &media[c];
      p.medium = media[1];
    } else {
      return sl::fail(kCmd, "--medium must be haze or fog", 2);
    }
  }
  if (!particle.empty()) {
    const int part = sl_particle_from_name(particle.c_str());
    if (part < 0) return sl::fail(kCmd, "--particle must be cloud, rain, ice or snow", 2);
    sl_optics_request req;
    sl_optics_request_defaults(&req); /* the paper's 650, 515, 440 nm */
    req.particles = 1u << part;
    {
      sl::Progress bar("optics tables", !o.has("quiet"));
      req.progress = progress_hook;
      req.progress_user = &bar;
      tables = sl_optics_build(&req, &err);
      bar.done();
    }
    if (!tables) return sl::fail(kCmd, err.message);
    for (int c = 0; c < 3; ++c) {
      const sl_phase_table *t = sl_optics_table(tables, (sl_particle)part, c);
      media[c] = sl_apsf_medium{t->albedo, t->moments[1], t->moments, t->n_moments};
      p.channel_medium[c] = &media[c];
    }
  }
  struct TablesGuard {
    sl_optics_tables *t;
    ~TablesGuard() { sl_optics_free(t); }
  } tables_guard{tables};
  sl_image img{};
  if (sl_read_exr(in_path.c_str(), &img, &err)) return sl::fail(kCmd, err.message); /* names the file */
  if (p.fixed_T <= 0) {
    // sl_read_exr reads a missing Z as +inf: a frame with no finite depth anywhere has no depth.
    bool any_finite = false;
    for (size_t i = 0; img.depth && i < (size_t)img.width * img.height && !any_finite; ++i)
      any_finite = std::isfinite(img.depth[i]);
    if (!any_finite && !(p.sky_distance > 0)) {
      sl_image_free(&img);
      return sl::fail(kCmd, in_path + ": no depth channel Z (or no finite depth in it): give --T or --sky-distance-km", 2);
    }
  }
  const bool quiet = o.has("quiet");
  const double t0 = sl::now_seconds();
  sl_glow_workspace *ws = sl_glow_workspace_create(img.width, img.height, 0, 0, &err);
  if (!ws) {
    sl_image_free(&img);
    return sl::fail(kCmd, in_path + ": " + err.message);
  }
  sl_glow_stats st;
  int rc;
  {
    sl::Progress bar("glow", !quiet);
    p.progress = progress_hook;
    p.progress_user = &bar;
    rc = sl_glow_apply(ws, &p, &img, &img, &st, &err);
    bar.done();
  }
  sl_glow_workspace_free(ws);
  if (rc) {
    sl_image_free(&img);
    return sl::fail(kCmd, in_path + ": " + err.message);
  }
  const double seconds = sl::now_seconds() - t0;
  rc = png ? sl_write_png(out_path.c_str(), &img, (float)exposure, &err)
           : sl_write_exr(out_path.c_str(), &img, SL_EXR_FLOAT, &err);
  sl_image_free(&img);
  if (rc) return sl::fail(kCmd, err.message);
  if (o.has("json")) {
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "input", in_path.c_str());
    cJSON_AddStringToObject(root, "output", out_path.c_str());
    if (p.fixed_T > 0) cJSON_AddNumberToObject(root, "T", p.fixed_T);
    else cJSON_AddNumberToObject(root, "sigma_per_m", p.sigma);
    if (tables || p.channel_medium[0]) {
      if (o.has("medium")) cJSON_AddStringToObject(root, "medium", o.str("medium").c_str());
      if (tables) cJSON_AddStringToObject(root, "particle", particle.c_str());
      cJSON_AddItemToObject(root, "sigma_scale_rgb", cJSON_CreateDoubleArray(p.channel_sigma_scale, 3));
      double g[3], a[3];
      for (int c = 0; c < 3; ++c) g[c] = media[c].q, a[c] = media[c].albedo;
      cJSON_AddItemToObject(root, "asymmetry_rgb", cJSON_CreateDoubleArray(g, 3));
      cJSON_AddItemToObject(root, "albedo_rgb", cJSON_CreateDoubleArray(a, 3));
    } else {
      cJSON_AddNumberToObject(root, "q", p.medium.q);
      cJSON_AddNumberToObject(root, "albedo", p.medium.albedo);
    }
    cJSON_AddNumberToObject(root, "source_pixels", st.sources);
    cJSON_AddNumberToObject(root, "T_min", st.T_min);
    cJSON_AddNumberToObject(root, "T_max", st.T_max);
    cJSON_AddItemToObject(root, "layer_T", cJSON_CreateDoubleArray(st.layer_T, st.layers_used));
    cJSON_AddItemToObject(root, "layer_terms", cJSON_CreateIntArray(st.layer_terms, st.layers_used));
    cJSON_AddNumberToObject(root, "kernel_seconds", st.kernel_seconds);
    cJSON_AddNumberToObject(root, "convolve_seconds", st.convolve_seconds);
    cJSON_AddNumberToObject(root, "seconds", seconds);
    cJSON_AddStringToObject(root, "normalisation", norm.c_str());
    char *text = cJSON_PrintUnformatted(root);
    std::printf("%s\n", text);
    std::free(text);
    cJSON_Delete(root);
  } else if (!quiet) {
    std::printf("%s: %d source pixels, T %.3g..%.3g, %d layers convolved in %.2f s -> %s\n", in_path.c_str(), st.sources,
                st.T_min, st.T_max, st.layers_used, seconds, out_path.c_str());
  }
  return 0;
}
