/* What the command line's number-computing subcommands give: a storm file's contents (`info`),
 * the sun (`sun`), the sky (`sky`) and the particles' optics (`optics`). */
#include "extension.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A list of str from count fixed-size C strings. */
static PyObject *text_list(const char (*texts)[24], int count)
{
  PyObject *list = PyList_New(count);
  for (int i = 0; list && i < count; ++i) {
    PyObject *s = PyUnicode_FromString(texts[i]);
    if (!s) Py_CLEAR(list);
    else PyList_SET_ITEM(list, i, s);
  }
  return list;
}

/* storm_info(path) -> dict: what sl_storm_read_info finds in a storm file without loading it
 * (kind, grid, projection, scheme, species, times). */
PyObject *slpy_storm_info(PyObject *Py_UNUSED(module), PyObject *args)
{
  PyObject *path_obj;
  if (!PyArg_ParseTuple(args, "O&", PyUnicode_FSConverter, &path_obj)) return NULL;
  sl_storm_info *info = malloc(sizeof *info);
  if (!info) {
    Py_DECREF(path_obj);
    return PyErr_NoMemory();
  }
  sl_error err = {0};
  int rc;
  Py_BEGIN_ALLOW_THREADS
  rc = sl_storm_read_info(PyBytes_AS_STRING(path_obj), info, &err);
  Py_END_ALLOW_THREADS
  Py_DECREF(path_obj);
  if (rc) {
    free(info);
    return slpy_raise(&err);
  }
  PyObject *species = PyList_New(0);
  for (int i = 0; species && i < info->nspecies; ++i) {
    const sl_species *sp = &info->species[i];
    PyObject *d = Py_BuildValue("{s:s,s:s,s:s,s:s,s:s,s:O}", "variable", sp->variable, "number_variable",
                                sp->number_variable, "kind", sp->kind ? sp->kind : "",
                                "type", sl_particle_name((sl_particle)sp->warm), "type_below_0C",
                                sl_particle_name((sl_particle)sp->cold), "sized",
                                sl_species_sized(sp) ? Py_True : Py_False);
    if (!d || PyList_Append(species, d)) Py_CLEAR(species);
    Py_XDECREF(d);
  }
  PyObject *elapsed = PyList_New(0);
  for (int i = 0; elapsed && info->has_elapsed && i < info->ntimes; ++i) {
    PyObject *x = PyFloat_FromDouble(info->elapsed_s[i]);
    if (!x || PyList_Append(elapsed, x)) Py_CLEAR(elapsed);
    Py_XDECREF(x);
  }
  const int nt = info->has_times ? (info->ntimes < SL_MAX_TIMES ? info->ntimes : SL_MAX_TIMES) : 0;
  const char *kind = sl_storm_kind_name(info->kind);
  PyObject *out = species && elapsed
                      ? Py_BuildValue("{s:s,s:s,s:i,s:(iii),s:i,s:(dd),s:i,s:s,s:s,s:N,s:N,s:s,s:N,s:N}", "path",
                                      info->path, "kind", kind, "format", info->format, "shape", info->nx, info->ny,
                                      info->nz, "ntimes", info->ntimes, "spacing", info->dx, info->dy, "map_proj",
                                      info->map_proj, "scheme", info->scheme, "vertical", info->vertical,
                                      "species", species, "times", text_list(info->times, nt), "calendar",
                                      info->calendar, "sun_times", text_list(info->sun_times, nt),
                                      "elapsed_seconds", elapsed)
                      : NULL;
  if (!out) {
    Py_XDECREF(species);
    Py_XDECREF(elapsed);
  }
  free(info);
  return out;
}

/* info_json(args) -> str: `stormlight info --json` of the storm file and load options in render's
 * arguments (the file first), by the same C (sl_storm_info_json). */
PyObject *slpy_info_json(PyObject *Py_UNUSED(module), PyObject *args)
{
  PyObject *list;
  if (!PyArg_ParseTuple(args, "O", &list)) return NULL;
  sl_settings *s = malloc(sizeof *s);
  if (!s) return PyErr_NoMemory();
  PyObject *out = NULL;
  if (!slpy_settings_from_args(list, s, 0)) {
    sl_load_options load;
    sl_settings_load_options(s, 0, &load);
    sl_error err = {0};
    char *text;
    Py_BEGIN_ALLOW_THREADS
    text = sl_storm_info_json(s->data, &load, &err);
    Py_END_ALLOW_THREADS
    out = text ? PyUnicode_FromString(text) : slpy_raise(&err);
    free(text);
  }
  free(s);
  return out;
}

/* sun_position(iso8601, lat, lon) -> dict: the sun's apparent position (sl_solar_position_compute,
 * with refraction, as `stormlight sun`). */
PyObject *slpy_sun_position(PyObject *Py_UNUSED(module), PyObject *args)
{
  const char *when;
  double lat, lon;
  if (!PyArg_ParseTuple(args, "sdd", &when, &lat, &lon)) return NULL;
  sl_utc t;
  sl_solar_position p;
  sl_error err = {0};
  if (sl_utc_parse_iso8601(when, &t, &err) || sl_solar_position_compute(&t, lat, lon, NULL, &p, &err))
    return slpy_raise(&err);
  return Py_BuildValue("{s:d,s:d,s:d,s:d,s:d,s:d,s:d,s:N,s:O}", "elevation", p.elevation_deg, "azimuth",
                       p.azimuth_deg, "zenith", p.zenith_deg, "elevation_true", p.elevation_true_deg, "declination",
                       p.declination_deg, "hour_angle", p.hour_angle_deg, "julian_day", p.julian_day, "direction",
                       slpy_vector3(p.direction), "night", p.night ? Py_True : Py_False);
}

/* optics(particle, wavelength_nm, angles_rad, order) -> dict: the particle type's table at one
 * wavelength (built by render/optics, or read from its on-disk cache): extinction cross-section,
 * albedo, asymmetry, the truncated forward fraction f, the forward fractions F_n, and the smooth
 * part of Ams_order at the given angles (bytes of float64, 1/sr; the forward Dirac of weight f^n
 * is apart). */
PyObject *slpy_optics(PyObject *Py_UNUSED(module), PyObject *args)
{
  const char *name;
  double wavelength;
  Py_buffer angles = {0};
  int order;
  if (!PyArg_ParseTuple(args, "sdy*i", &name, &wavelength, &angles, &order)) return NULL;
  const int p = sl_particle_from_name(name);
  PyObject *out = NULL;
  double *values = NULL;
  const size_t n = (size_t)angles.len / sizeof(double);
  if (p < 0) {
    PyErr_Format(PyExc_ValueError, "unknown particle '%s' (cloud, rain, ice, snow, graupel, hail)", name);
  } else if (!(wavelength >= 200.0 && wavelength <= 3000.0)) {
    PyErr_Format(PyExc_ValueError, "wavelength %g nm is outside 200..3000 nm", wavelength);
  } else if (order < 1) {
    PyErr_SetString(PyExc_ValueError, "order must be >= 1");
  } else if (!(values = malloc((n ? n : 1) * sizeof *values))) {
    PyErr_NoMemory();
  } else {
    sl_optics_request req;
    sl_optics_request_defaults(&req);
    req.particles = 1u << p;
    req.n_wavelengths = 1;
    req.wavelengths_nm[0] = wavelength;
    sl_error err = {0};
    sl_optics_tables *tables;
    Py_BEGIN_ALLOW_THREADS
    tables = sl_optics_build(&req, &err);
    Py_END_ALLOW_THREADS
    const sl_phase_table *t = tables ? sl_optics_table(tables, (sl_particle)p, 0) : NULL;
    if (!t) {
      if (!err.code) sl_fail(&err, SL_ERR_ARG, "no table for %s at %g nm", name, wavelength);
      slpy_raise(&err);
    } else if (order > t->max_order) {
      PyErr_Format(PyExc_ValueError, "order %d is past the table's last order %d (isotropic from there)", order,
                   t->max_order);
    } else {
      const double *theta = angles.buf;
      for (size_t i = 0; i < n; ++i) {
        const double a = theta[i] < 0.0 ? 0.0 : theta[i] > M_PI ? M_PI : theta[i];
        values[i] = sl_phase_table_ams_theta(t, order, a);
      }
      PyObject *forward = slpy_double_list(t->forward, t->max_order + 1);
      out = forward ? Py_BuildValue("{s:d,s:d,s:d,s:d,s:d,s:d,s:i,s:N,s:N}", "wavelength", t->wavelength_nm,
                                    "sigma_ext", t->sigma_ext, "particle_mass", sl_particle_mass((sl_particle)p), "albedo", t->albedo, "asymmetry", t->asymmetry, "truncated_fraction",
                                    t->truncated_fraction, "max_order", t->max_order, "forward", forward, "ams",
                                    PyBytes_FromStringAndSize((const char *)values, (Py_ssize_t)(n * sizeof *values)))
                    : NULL;
    }
    sl_optics_free(tables);
  }
  free(values);
  PyBuffer_Release(&angles);
  return out;
}


/* sky(eye_height, view_elevation, view_azimuth, sun_elevation, sun_azimuth, distance, round_earth,
 * spectral) -> dict: as `stormlight sky --json`, the single-scattered sky radiance along the view
 * ray to distance (inf: the top of the air) and its transparency per wavelength, the sunlight at
 * the eye, for a top-of-atmosphere sun of irradiance 1 (sl_sky_segment, sl_sky_sunlight). */
PyObject *slpy_sky(PyObject *Py_UNUSED(module), PyObject *args)
{
  double eye_height, view_el, view_az, sun_el, sun_az, distance;
  int round_earth, spectral;
  if (!PyArg_ParseTuple(args, "ddddddpp", &eye_height, &view_el, &view_az, &sun_el, &sun_az, &distance, &round_earth,
                        &spectral))
    return NULL;
  if (!(view_el >= -90 && view_el <= 90 && sun_el >= -90 && sun_el <= 90) || !(eye_height >= -500 && eye_height <= 1e6) ||
      !(distance >= 0)) {
    PyErr_SetString(PyExc_ValueError, "elevations must lie in [-90, 90] degrees, the eye in [-500, 1e6] m, "
                                      "the distance >= 0");
    return NULL;
  }
  double wavelengths[SL_SKY_SPECTRAL_COUNT];
  int count = SL_SKY_RGB_COUNT;
  if (spectral) sl_sky_spectral_wavelengths(wavelengths), count = SL_SKY_SPECTRAL_COUNT;
  else memcpy(wavelengths, sl_sky_rgb_wavelengths_nm, sizeof(double) * SL_SKY_RGB_COUNT);
  sl_atmosphere atm;
  sl_error err = {0};
  double sun[3], dir[3], radiance[SL_SKY_SPECTRAL_COUNT], transparency[SL_SKY_SPECTRAL_COUNT];
  double sunlight[SL_SKY_SPECTRAL_COUNT];
  const double eye[3] = {0.0, 0.0, eye_height};
  sl_sun_direction(sun_el, sun_az, sun);
  sl_sun_direction(view_el, view_az, dir);
  int night = 0;
  if (sl_atmosphere_init(&atm, wavelengths, count, round_earth ? SL_EARTH_ROUND : SL_EARTH_FLAT,
                         SL_RAYLEIGH_BODHAINE1999, &err) ||
      sl_sky_segment(&atm, eye, dir, distance, sun, radiance, transparency, &night, &err) ||
      sl_sky_sunlight(&atm, eye, sun, sunlight, NULL, &err))
    return slpy_raise(&err);
  return Py_BuildValue("{s:N,s:N,s:d,s:N,s:N,s:N,s:O}", "wavelengths_nm", slpy_double_list(atm.wavelength_nm, count),
                       "beta_sea_level", slpy_double_list(atm.beta_sea_level, count), "scale_height_m", atm.scale_height,
                       "radiance", slpy_double_list(radiance, count), "transparency", slpy_double_list(transparency, count),
                       "sunlight_at_eye", slpy_double_list(sunlight, count), "night", night ? Py_True : Py_False);
}

