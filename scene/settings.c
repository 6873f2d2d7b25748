/* The scene's options: one table (name, type, range, default, help) and the parser that fills an
 * sl_settings from text, whether the text came from a command line or a scene file. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sl_renderer.h"
#include "sl_settings.h"

#define AT(field) offsetof(sl_settings, field)

static int parse_date(sl_settings *s, const char *v, sl_error *err);
static int parse_origin(sl_settings *s, const char *v, sl_error *err);
static int parse_fields(sl_settings *s, const char *v, sl_error *err);
static int parse_droplets(sl_settings *s, const char *v, sl_error *err);
static int parse_region(sl_settings *s, const char *v, sl_error *err);
static int parse_levels(sl_settings *s, const char *v, sl_error *err);
static int parse_memory(sl_settings *s, const char *v, sl_error *err);
static int parse_lights_count(sl_settings *s, const char *v, sl_error *err);

static const int lighting_values[] = {SL_LIGHTING_MULTIPLE, SL_LIGHTING_MULTIPLE_EQ25, SL_LIGHTING_LOW_ALBEDO};

/* name, metavar, help, default, type, min, max, choices, values, offset, parse */
const sl_option sl_settings_options[] = {
    {"out", "FILES", "output image(s), comma-separated: .exr (linear HDR) and/or .png (tone-mapped)", NULL,
     SL_OPTION_TEXT, 0, 0, NULL, NULL, AT(out), NULL},
    {"time", "N", "time index in the file", "0", SL_OPTION_INT, 0, 4095, NULL, NULL, AT(time_index), NULL},
    {"width", "PX", "image width", "512", SL_OPTION_INT, 1, 16384, NULL, NULL, AT(width), NULL},
    {"height", "PX", "image height", "512", SL_OPTION_INT, 1, 16384, NULL, NULL, AT(height), NULL},
    {"slices", "N", "slicing planes across the volume (0 = enough to resolve the grid)", "0", SL_OPTION_INT, 0, 16384,
     NULL, NULL, AT(slices), NULL},
    {"light-resolution", "N",
     "square light-buffer texels along its longer side (0 = automatic: per axis, about a pixel at the cloud, at most a "
     "grid cell)",
     "0", SL_OPTION_INT, 0, 8192, NULL, NULL, AT(light_resolution), NULL},
    {"sun-azimuth", "DEG", "sun azimuth, clockwise from north (with --sun-elevation; default: from the date)", NULL,
     SL_OPTION_NUMBER, -360, 360, NULL, NULL, AT(sun_azimuth_deg), NULL},
    {"sun-elevation", "DEG", "sun elevation above the horizon (with --sun-azimuth)", NULL, SL_OPTION_NUMBER, -90, 90,
     NULL, NULL, AT(sun_elevation_deg), NULL},
    {"date", "ISO8601", "UTC date-time that places the sun over the grid's centre (default: the file's time)", NULL,
     SL_OPTION_SPECIAL, 0, 0, NULL, NULL, 0, parse_date},
    {"earth", "flat|round", "air mass of the sunlight: the paper's flat earth or a spherical one", "round",
     SL_OPTION_CHOICE, 0, 0, "round|flat", NULL, AT(flat_earth), NULL},
    {"curvature", "flat|drop",
     "storm columns on the tangent plane (flat) or sunk by the sphere's depth below it\n"
     "(drop: r^2/2R, 19.6 km at 500 km; docs/GEOREFERENCING.md)",
     "flat", SL_OPTION_CHOICE, 0, 0, "flat|drop", NULL, AT(curvature_drop), NULL},
    {"origin", "LAT,LON", "tangent point of the world frame (default: the grid's centre at this time)", NULL,
     SL_OPTION_SPECIAL, 0, 0, NULL, NULL, 0, parse_origin},
    {"lighting", "MODEL", "multiple (Riley eqs. 16-26 with eq. 24), eq25 (the paper's eq. 25), low-albedo (Fig. 13)",
     "multiple", SL_OPTION_CHOICE, 0, 0, "multiple|eq25|low-albedo", lighting_values, AT(lighting), NULL},
    {"xi", "XI",
     "eq. 26's back-scattering term added to Ams, 1/sr: light that higher orders return and the\n"
     "forward-only light buffer discards; with --diffuse-sunlight on (the default) that light is\n"
     "modelled, so 0; the paper's model (--diffuse-sunlight off) wants about 0.05",
     "0", SL_OPTION_NUMBER, 0, 1e3, NULL, NULL, AT(xi), NULL},
    {"wavelengths", "SET", "rgb (650, 515, 440 nm as red, green, blue) or spectral (16 from 380 to 720 nm via CIE)",
     "rgb", SL_OPTION_CHOICE, 0, 0, "rgb|spectral", NULL, AT(spectral), NULL},
    {"fog-visibility-km", "V",
     "glows (Narasimhan et al.) of bright sources seen through fog of small droplets (cloud tables) with this "
     "visibility; 0 = none",
     "0", SL_OPTION_NUMBER, 0, 1e6, NULL, NULL, AT(fog_visibility_km), NULL},
    {"fog-type", "fog|haze",
     "with --fog-visibility-km: fog (small droplets, cloud tables) or haze (Shettle & Fenn's rural aerosol through "
     "Mie, not grey)",
     "fog", SL_OPTION_CHOICE, 0, 0, "fog|haze", NULL, AT(fog_haze), NULL},
    {"fog-depth-km", "D",
     "with fog: how deep the fog bank in front of the camera is (what lies farther is seen through all of it)", "2",
     SL_OPTION_NUMBER, 0, 1e6, NULL, NULL, AT(fog_depth_km), NULL},
    {"light-volume", NULL, "light a cached view-independent light volume once, then ray-march (fast camera moves)",
     NULL, SL_OPTION_FLAG, 0, 0, NULL, NULL, AT(light_volume), NULL},
    {"march-samples", "N",
     "with --light-volume or --gpu: eye samples per grid cell along a ray, 1..8 (more is\n"
     "slower and nearer the march's limit; docs/ACCURACY.md, \"The march's steps\")",
     "1", SL_OPTION_INT, 1, 8, NULL, NULL, AT(march_samples), NULL},
    {"march-thin-depth", "T",
     "with --light-volume: where two or four steps through a thin brick add up to at most this optical\n"
     "depth, take them as one (fewer samples through thin anvils, rain and haze; docs/ACCURACY.md,\n"
     "\"Thin steps\"); 0: every step",
     "0", SL_OPTION_NUMBER, 0, 1, NULL, NULL, AT(march_thin_depth), NULL},
    {"march-refine", "TOL",
     "with --light-volume: march every 4th pixel's ray first and interpolate inside blocks whose\n"
     "halfway rays agree with their corners' within this fraction, refining the others down to\n"
     "every pixel (docs/ACCURACY.md, \"Adaptive pixels\"); 0: a ray per pixel",
     "0", SL_OPTION_NUMBER, 0, 1, NULL, NULL, AT(march_refine_tolerance), NULL},
    {"skylight", "on|off",
     "the sky dome's light scattered by the volume too (shadowed faces lit blue, a dark base over\n"
     "a dark ground; docs/ACCURACY.md, \"Skylight\"), or the sun alone (the paper's model)",
     "on", SL_OPTION_CHOICE, 0, 0, "off|on", NULL, AT(skylight), NULL},
    {"diffuse-sunlight", "on|off",
     "sunlight scattered through the cloud out of the light buffer's forward cone lights the volume\n"
     "too (faces in the storm's own shadow, the inside of thick cloud; docs/ACCURACY.md, \"Diffuse\n"
     "sunlight\"), or the light buffer alone (the paper's model, which --xi then stands in for)",
     "on", SL_OPTION_CHOICE, 0, 0, "off|on", NULL, AT(diffuse_sunlight), NULL},
    {"ground-albedo", "A",
     "albedo of the flat ground at sea level under the storm (without --terrain), lit by the sun\n"
     "through the storm's shadow and by the sky (land 0.15, sea 0.06; 0: black, only the air in front shines);\n"
     "not given: the domain's mean of the file's ALBEDO, else of its LANDMASK or XLAND, else 0.15",
     "0.15", SL_OPTION_NUMBER, 0, 1, NULL, NULL, AT(ground_albedo), NULL},
    {"no-atmosphere", NULL, "no air: unattenuated white sunlight and the constant --sky behind the volume", NULL,
     SL_OPTION_FLAG, 0, 0, NULL, NULL, AT(no_atmosphere), NULL},
    {"camera-position", "X,Y,Z",
     "camera position, metres east, north, up. Default: a storm chaser's view, 2 m above the\n"
     "ground with the sun 30 degrees round from behind the left shoulder, looking back at the storm\n"
     "and up so the horizon sits a quarter up the frame, as near as fits the storm's top and its\n"
     "core's width (columns of optical depth 100); a storm too wide for that (a deck, a hurricane),\n"
     "or --view-azimuth/--view-elevation given: the orbit camera", NULL,
     SL_OPTION_LIST, 3, 0, NULL, NULL, AT(camera_position), NULL},
    {"camera-target", "X,Y,Z", "point the camera looks at (default: the cloud's centre)", NULL, SL_OPTION_LIST, 3, 0,
     NULL, NULL, AT(camera_target), NULL},
    {"view-azimuth", "DEG", "orbit camera: compass direction from the cloud to the camera", "200", SL_OPTION_NUMBER,
     -360, 360, NULL, NULL, AT(view_azimuth_deg), NULL},
    {"view-elevation", "DEG", "orbit camera: elevation of the camera seen from the cloud", "12", SL_OPTION_NUMBER, -90,
     90, NULL, NULL, AT(view_elevation_deg), NULL},
    {"fov", "DEG", "vertical field of view", "40", SL_OPTION_NUMBER, 0, 170, NULL, NULL, AT(fov_deg), NULL},
    {"threads", "N", "OpenMP threads (0 = all cores)", "0", SL_OPTION_INT, 0, 4096, NULL, NULL, AT(threads), NULL},
    {"exposure", "E", "PNG tone mapping: 1 - exp(-E L)", "12", SL_OPTION_NUMBER, 0, 1e12, NULL, NULL, AT(exposure),
     NULL},
    {"sky", "R,G,B", "with --no-atmosphere: the constant sky radiance", "0.035,0.055,0.10", SL_OPTION_LIST, 3, 0, NULL,
     NULL, AT(sky), NULL},
    {"dz", "M", "vertical spacing of the uniform grid (0 = half the mean model layer)", "0", SL_OPTION_NUMBER, 0, 1e5,
     NULL, NULL, AT(dz), NULL},
    {"float", NULL, "write 32-bit float EXR channels instead of half", NULL, SL_OPTION_FLAG, 0, 0, NULL, NULL,
     AT(float_exr), NULL},
    {"field", "TYPE=VAR,...",
     "feed particle TYPE (cloud, rain, ice, snow, graupel, hail) from file variable VAR\n"
     "instead of the scheme's mapping (VAR 'none': leave TYPE out; CM1 run with ihail=1: hail=qg); see docs/DATA.md",
     NULL, SL_OPTION_SPECIAL, 0, 0, NULL, NULL, 0, parse_fields},
    {"particles", "sizes|representative",
     "sizes: each cell's effective radius from the scheme's size distribution\n"
     "and number concentration scales its extinction and picks its cloud and rain phase functions;\n"
     "representative: one particle per type (Riley et al. 2004)",
     "sizes", SL_OPTION_CHOICE, 0, 0, "sizes|representative", NULL, AT(representative_particles), NULL},
    {"max-fields", "N",
     "particle fields the renderer carries per sample, 1..8 (--gpu too); cloud and rain\n"
     "take tables at a few effective radii in what the species leave: fewer fields, fewer tables, faster\n"
     "samples (docs/DATA.md, \"Optics at each cell's size\")",
     "8", SL_OPTION_INT, 1, SL_VOLUME_MAX_FIELDS, NULL, NULL, AT(max_fields), NULL},
    {"droplet-number", "CM3",
     "cloud droplets per cm^3 where the file writes no droplet number (CM1's namelist\n"
     "ndcnst; default: the scheme's, Morrison 250, Thompson 100)",
     NULL, SL_OPTION_SPECIAL, 0, 0, NULL, NULL, 0, parse_droplets},
    {"region", "LAT0,LAT1,LON0,LON1", "read only the grid columns inside these latitudes/longitudes (WRF)", NULL,
     SL_OPTION_SPECIAL, 0, 0, NULL, NULL, 0, parse_region},
    {"levels", "K0:K1", "read only model levels K0..K1 (0-based, inclusive)", NULL, SL_OPTION_SPECIAL, 0, 0, NULL, NULL,
     0, parse_levels},
    {"stride", "N", "read every N-th column in x and y", "1", SL_OPTION_INT, 1, 100000, NULL, NULL, AT(stride), NULL},
    {"max-memory", "BYTES", "refuse a load whose estimate exceeds this (e.g. 8G; default: the memory available)", NULL,
     SL_OPTION_SPECIAL, 0, 0, NULL, NULL, 0, parse_memory},
    {"terrain", NULL, "draw the terrain (HGT) as a lit surface: eye rays stop at it, the storm shadows it", NULL,
     SL_OPTION_FLAG, 0, 0, NULL, NULL, AT(terrain), NULL},
    {"terrain-albedo", "A", "terrain albedo (default: the file's ALBEDO, else land 0.15, water 0.06)", NULL,
     SL_OPTION_NUMBER, 0, 1, NULL, NULL, AT(terrain_albedo), NULL},
    {"coastlines", NULL, "draw GSHHG coastlines (GMT) draped on the terrain", NULL, SL_OPTION_FLAG, 0, 0, NULL, NULL,
     AT(coastlines), NULL},
    {"borders", NULL, "draw national borders (DCW through GMT) draped on the terrain", NULL, SL_OPTION_FLAG, 0, 0, NULL,
     NULL, AT(borders), NULL},
    {"graticule", NULL, "draw a latitude/longitude graticule", NULL, SL_OPTION_FLAG, 0, 0, NULL, NULL, AT(graticule),
     NULL},
    {"graticule-step", "DEG", "graticule spacing in degrees (0 = 3 to 8 lines across the domain)", "0",
     SL_OPTION_NUMBER, 0, 90, NULL, NULL, AT(graticule_step), NULL},
    {"domain-outline", NULL, "draw the outline of the model domain", NULL, SL_OPTION_FLAG, 0, 0, NULL, NULL,
     AT(domain_outline), NULL},
    {"scale-bar", NULL, "draw a scale bar in the domain's south-west corner", NULL, SL_OPTION_FLAG, 0, 0, NULL, NULL,
     AT(scale_bar), NULL},
    {"night-sky-luminance", "CD_M2",
     "luminance of the sky above the horizon, cd/m^2, added to the analytic sky (which\n"
     "is 0 once the sun is down): e.g. 2e-4 for a moonless natural night sky",
     "0", SL_OPTION_NUMBER, 0, 1e6, NULL, NULL, AT(night_sky_luminance), NULL},
    {"lights-count", "NX,NY", "a town of NX x NY emissive street lamps on the ground (default: none)", NULL,
     SL_OPTION_SPECIAL, 0, 0, NULL, NULL, 0, parse_lights_count},
    {"lights-center", "X,Y", "the town's centre, metres east, north in the world frame", "0,0", SL_OPTION_LIST, 2, 0,
     NULL, NULL, AT(lights_center), NULL},
    {"lights-spacing", "M", "distance between neighbouring lamps", "150", SL_OPTION_NUMBER, 0, 1e7, NULL, NULL,
     AT(lights_spacing), NULL},
    {"lights-height", "M", "lamp height above the ground (the file's HGT)", "10", SL_OPTION_NUMBER, -1e5, 1e5, NULL,
     NULL, AT(lights_height), NULL},
    {"lights-jitter", "F", "each lamp moved by up to +-F/2 of the spacing (seeded, reproducible)", "0.6",
     SL_OPTION_NUMBER, 0, 1e3, NULL, NULL, AT(lights_jitter), NULL},
    {"lights-intensity-cd", "CD", "luminous intensity of one lamp toward the camera, cd (isotropic)", "1000",
     SL_OPTION_NUMBER, 0, 1e12, NULL, NULL, AT(lights_intensity_cd), NULL},
    {"lights-color", "R,G,B",
     "lamp colour as relative linear-sRGB weights (scaled to unit luminance; default: high-pressure\n"
     "sodium, chromaticity x 0.52, y 0.42)",
     "1,0.29,0.01", SL_OPTION_LIST, 3, 0, NULL, NULL, AT(lights_color), NULL},
};
const int sl_settings_option_count = (int)(sizeof sl_settings_options / sizeof sl_settings_options[0]);
_Static_assert(sizeof sl_settings_options / sizeof sl_settings_options[0] <= sizeof((sl_settings *)0)->given,
               "sl_settings.given holds one flag per option");

const sl_option *sl_settings_option(const char *name)
{
  for (int i = 0; i < sl_settings_option_count; ++i)
    if (strcmp(sl_settings_options[i].name, name) == 0) return &sl_settings_options[i];
  return NULL;
}

static int parse_number(const char *text, double *out)
{
  char *end = NULL;
  errno = 0;
  const double v = strtod(text, &end);
  if (!*text || end == text || *end != '\0' || errno != 0 || !isfinite(v)) return 0;
  *out = v;
  return 1;
}

/* count comma-separated numbers of text into out; 0 when the text holds another count or a
 * value that is not a finite number. */
static int parse_list(const char *text, int count, double *out)
{
  char buf[512];
  if (strlen(text) >= sizeof buf) return 0;
  strcpy(buf, text);
  int n = 0;
  char *save = NULL;
  for (char *item = strtok_r(buf, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
    if (n == count || !parse_number(item, &out[n])) return 0;
    n++;
  }
  return n == count && text[strlen(text) - 1] != ',';
}

static int parse_date(sl_settings *s, const char *v, sl_error *err)
{
  sl_error e = {0};
  if (sl_utc_parse_iso8601(v, &s->date, &e)) return sl_fail(err, SL_ERR_ARG, "--date: %s", e.message);
  return SL_OK;
}

static int parse_origin(sl_settings *s, const char *v, sl_error *err)
{
  if (!parse_list(v, 2, s->origin) || !(fabs(s->origin[0]) <= 90.0))
    return sl_fail(err, SL_ERR_ARG, "--origin needs LAT,LON in degrees");
  return SL_OK;
}

static int parse_fields(sl_settings *s, const char *v, sl_error *err)
{
  char buf[1024];
  if (strlen(v) >= sizeof buf) return sl_fail(err, SL_ERR_ARG, "--field: the list is too long");
  strcpy(buf, v);
  char *save = NULL;
  for (char *item = strtok_r(buf, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
    char *eq = strchr(item, '=');
    int type = -1;
    if (eq) {
      *eq = '\0';
      type = sl_particle_from_name(item);
      *eq = '=';
    }
    if (type < 0 || !eq[1] || strlen(eq + 1) >= SL_SETTINGS_VARIABLE)
      return sl_fail(err, SL_ERR_ARG,
                     "--field: '%s' is not TYPE=VARIABLE with TYPE one of cloud, rain, ice, snow, graupel, hail", item);
    strcpy(s->field_variable[type], eq + 1);
  }
  return SL_OK;
}

static int parse_droplets(sl_settings *s, const char *v, sl_error *err)
{
  double n;
  if (!parse_number(v, &n) || !(n > 0.0 && n <= 1e5))
    return sl_fail(err, SL_ERR_ARG, "--droplet-number: %s is not 0..1e5 per cm^3", v);
  s->droplet_number_cm3 = n;
  return SL_OK;
}

static int parse_region(sl_settings *s, const char *v, sl_error *err)
{
  double r[4];
  if (!parse_list(v, 4, r) || !(r[0] < r[1]) || r[0] < -90 || r[1] > 90 || r[2] < -360 || r[3] > 360)
    return sl_fail(err, SL_ERR_ARG, "--region needs LAT0,LAT1,LON0,LON1 in degrees with LAT0 < LAT1");
  memcpy(s->region, r, sizeof r);
  return SL_OK;
}

static int parse_levels(sl_settings *s, const char *v, sl_error *err)
{
  int k0, k1;
  char tail;
  if (sscanf(v, "%d:%d%c", &k0, &k1, &tail) != 2 || k0 < 0 || k1 < k0)
    return sl_fail(err, SL_ERR_ARG, "--levels needs K0:K1 with 0 <= K0 <= K1");
  s->level_first = k0, s->level_count = k1 - k0 + 1;
  return SL_OK;
}

static int parse_memory(sl_settings *s, const char *v, sl_error *err)
{
  char *end = NULL;
  errno = 0;
  const double x = strtod(v, &end);
  static const char *const units[] = {"", "K", "M", "G", "T"};
  if (*v && errno == 0 && end != v && isfinite(x) && x > 0)
    for (int i = 0; i < 5; ++i) {
      char b[4], ib[5];
      snprintf(b, sizeof b, "%sB", units[i]);
      snprintf(ib, sizeof ib, "%siB", units[i]);
      if (strcmp(end, units[i]) == 0 || (i > 0 && (strcmp(end, b) == 0 || strcmp(end, ib) == 0))) {
        s->max_memory = x * pow(1024.0, i);
        return SL_OK;
      }
    }
  return sl_fail(err, SL_ERR_ARG, "--max-memory: '%s' is not a size such as 8G, 512M or 1e9", v);
}

static int parse_lights_count(sl_settings *s, const char *v, sl_error *err)
{
  double n[2];
  if (!parse_list(v, 2, n) || n[0] != floor(n[0]) || n[1] != floor(n[1]) || !(n[0] >= 1 && n[1] >= 1) ||
      n[0] * n[1] > 1e6)
    return sl_fail(err, SL_ERR_ARG, "--lights-count needs two whole numbers NX,NY >= 1 (at most 1e6 lamps)");
  s->lights_count[0] = (int)n[0], s->lights_count[1] = (int)n[1];
  return SL_OK;
}

int sl_settings_set(sl_settings *s, const char *name, const char *value, sl_error *err)
{
  const sl_option *o = sl_settings_option(name);
  if (!o) return sl_fail(err, SL_ERR_ARG, "unknown option --%s", name);
  const char *v = value ? value : "";
  char *at = (char *)s + o->offset;
  switch (o->type) {
  case SL_OPTION_FLAG:
    *(int *)at = 1;
    break;
  case SL_OPTION_INT: {
    char *end = NULL;
    errno = 0;
    const long x = strtol(v, &end, 10);
    if (!*v || *end != '\0' || errno != 0 || x < o->min || x > o->max)
      return sl_fail(err, SL_ERR_ARG, "option --%s: '%s' is not an integer in [%.0f, %.0f]", name, v, o->min, o->max);
    *(int *)at = (int)x;
    break;
  }
  case SL_OPTION_NUMBER: {
    double x;
    if (!parse_number(v, &x)) return sl_fail(err, SL_ERR_ARG, "option --%s: '%s' is not a finite number", name, v);
    if (x < o->min || x > o->max)
      return sl_fail(err, SL_ERR_ARG, "option --%s: %s is outside [%g, %g]", name, v, o->min, o->max);
    *(double *)at = x;
    break;
  }
  case SL_OPTION_CHOICE: {
    const char *c = o->choices;
    for (int i = 0; c && *c; ++i) {
      const char *bar = strchr(c, '|');
      const size_t len = bar ? (size_t)(bar - c) : strlen(c);
      if (strlen(v) == len && strncmp(v, c, len) == 0) {
        *(int *)at = o->values ? o->values[i] : i;
        goto set;
      }
      c = bar ? bar + 1 : NULL;
    }
    return sl_fail(err, SL_ERR_ARG, "option --%s: '%s' is not one of %s", name, v, o->choices);
  }
  case SL_OPTION_LIST: {
    double x[8];
    const int count = (int)o->min;
    if (!parse_list(v, count, x))
      return sl_fail(err, SL_ERR_ARG, "option --%s: '%s' is not %d comma-separated numbers", name, v, count);
    memcpy(at, x, count * sizeof(double));
    break;
  }
  case SL_OPTION_TEXT:
    if (strlen(v) >= SL_SETTINGS_PATH) return sl_fail(err, SL_ERR_ARG, "option --%s: the text is too long", name);
    strcpy(at, v);
    break;
  case SL_OPTION_SPECIAL: {
    const int rc = o->parse(s, v, err);
    if (rc) return rc;
    break;
  }
  }
set:
  s->given[o - sl_settings_options] = 1;
  return SL_OK;
}

int sl_settings_given(const sl_settings *s, const char *name)
{
  const sl_option *o = sl_settings_option(name);
  return o && s->given[o - sl_settings_options];
}

void sl_settings_defaults(sl_settings *s)
{
  memset(s, 0, sizeof *s);
  for (int i = 0; i < sl_settings_option_count; ++i) {
    const sl_option *o = &sl_settings_options[i];
    if (!o->fallback) continue;
    sl_error err = {0};
    /* The table's own defaults parse (tests/scene checks every one); given stays 0. */
    if (sl_settings_set(s, o->name, o->fallback, &err) == SL_OK) s->given[i] = 0;
  }
}

int sl_settings_parse_args(sl_settings *s, int argc, char **argv, sl_error *err)
{
  int positional = 0;
  for (int i = 0; i < argc; ++i) {
    const char *a = argv[i];
    if (strncmp(a, "--", 2) != 0) {
      if (positional++) return sl_fail(err, SL_ERR_ARG, "more than one storm file ('%s')", a);
      if (strlen(a) >= SL_SETTINGS_PATH) return sl_fail(err, SL_ERR_ARG, "the storm file's path is too long");
      strcpy(s->data, a);
      continue;
    }
    const sl_option *o = sl_settings_option(a + 2);
    if (!o) return sl_fail(err, SL_ERR_ARG, "unknown option %s", a);
    if (o->type != SL_OPTION_FLAG && i + 1 >= argc) return sl_fail(err, SL_ERR_ARG, "option %s needs a value", a);
    const int rc = sl_settings_set(s, o->name, o->type == SL_OPTION_FLAG ? NULL : argv[++i], err);
    if (rc) return rc;
  }
  return SL_OK;
}

int sl_settings_check(const sl_settings *s, sl_error *err)
{
  if (sl_settings_given(s, "sun-azimuth") != sl_settings_given(s, "sun-elevation"))
    return sl_fail(err, SL_ERR_ARG, "give both --sun-azimuth and --sun-elevation, or neither");
  if (sl_settings_given(s, "sun-azimuth") && sl_settings_given(s, "date"))
    return sl_fail(err, SL_ERR_ARG, "give --date or the sun's angles, not both");
  if (s->spectral && s->no_atmosphere) return sl_fail(err, SL_ERR_ARG, "--wavelengths spectral needs the atmosphere");
  if (!(s->fov_deg > 0.0 && s->fov_deg < 170.0))
    return sl_fail(err, SL_ERR_ARG, "--fov must be in (0, 170) degrees");
  return SL_OK;
}
