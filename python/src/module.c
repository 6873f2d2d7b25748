/* stormlight._stormlight: the Python package's extension over libstormlight (scene/stormlight.h).
 * Only the CPython API and the buffer protocol: frames leave as bytes that the package wraps in
 * numpy arrays without a copy (numpy.frombuffer), so the extension does not depend on numpy's C
 * API or its version. A Renderer holds one scene's settings and, once built, its storm, air,
 * tables and CPU renderer (plan once, render many); building and rendering release the GIL. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <pythread.h>

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "stormlight.h"

/* The OpenMP threads a render gets when it asks for none: the process's default at import (the
 * per-thread setting would otherwise keep the last render's). */
static int default_threads = 1;

/* A one-line error as the exception its kind calls for. */
static PyObject *raise_sl_error(const sl_error *err)
{
  PyObject *type = PyExc_RuntimeError;
  switch (err->code) {
  case SL_ERR_IO: type = PyExc_OSError; break;
  case SL_ERR_NOMEM: type = PyExc_MemoryError; break;
  case SL_ERR_FORMAT:
  case SL_ERR_DATA:
  case SL_ERR_ARG: type = PyExc_ValueError; break;
  default: break;
  }
  PyErr_SetString(type, err->message[0] ? err->message : "stormlight: unknown error");
  return NULL;
}

/* ---- Renderer ---- */

typedef struct {
  PyObject_HEAD
  sl_settings *settings;
  sl_built_scene *built;    /* NULL until built */
  PyThread_type_lock lock;  /* one build or render of this renderer at a time */
} Renderer;

static void renderer_release(Renderer *self)
{
  if (self->built) {
    sl_built_scene_free(self->built);
    free(self->built);
    self->built = NULL;
  }
}

static void renderer_dealloc(Renderer *self)
{
  renderer_release(self);
  free(self->settings);
  if (self->lock) PyThread_free_lock(self->lock);
  Py_TYPE(self)->tp_free((PyObject *)self);
}

/* Renderer(args): render's arguments (a storm file and "--option value" pairs), parsed by the
 * option table's parser and checked; nothing is loaded yet. */
static int renderer_init(Renderer *self, PyObject *args, PyObject *kwargs)
{
  static char *keywords[] = {"args", NULL};
  PyObject *list;
  if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O", keywords, &list)) return -1;
  PyObject *seq = PySequence_Fast(list, "Renderer: args must be a sequence of str");
  if (!seq) return -1;
  const Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
  char **argv = calloc((size_t)n + 1, sizeof *argv);
  int rc = argv ? 0 : -1;
  for (Py_ssize_t i = 0; !rc && i < n; ++i) {
    PyObject *item = PySequence_Fast_GET_ITEM(seq, i);
    const char *text = PyUnicode_Check(item) ? PyUnicode_AsUTF8(item) : NULL;
    if (!text) {
      if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "Renderer: args must be a sequence of str");
      rc = -1;
    } else {
      argv[i] = (char *)text; /* kept alive by seq */
    }
  }
  if (!argv) PyErr_NoMemory();
  if (!rc) {
    renderer_release(self);
    if (!self->settings) self->settings = malloc(sizeof *self->settings);
    if (!self->lock) self->lock = PyThread_allocate_lock();
    if (!self->settings || !self->lock) {
      PyErr_NoMemory();
      rc = -1;
    }
  }
  if (!rc) {
    sl_error err = {0};
    sl_settings_defaults(self->settings);
    if (sl_settings_parse_args(self->settings, (int)n, argv, &err) || sl_settings_check(self->settings, &err)) {
      raise_sl_error(&err);
      rc = -1;
    }
  }
  free(argv);
  Py_DECREF(seq);
  return rc;
}

/* Builds the scene if it is not built; called with the GIL released and the lock held. */
static int renderer_ensure_built(Renderer *self, sl_error *err)
{
  if (self->built) return SL_OK;
  sl_built_scene *b = calloc(1, sizeof *b);
  if (!b) return sl_fail(err, SL_ERR_NOMEM, "out of memory");
  const int rc = sl_scene_build(self->settings, NULL, b, err);
  if (rc) {
    free(b);
    return rc;
  }
  self->built = b;
  return SL_OK;
}

/* The same from Python's side: the GIL released, the lock taken. */
static int renderer_build_unlocked(Renderer *self, sl_error *err)
{
  int rc;
  Py_BEGIN_ALLOW_THREADS
  PyThread_acquire_lock(self->lock, WAIT_LOCK);
  rc = renderer_ensure_built(self, err);
  PyThread_release_lock(self->lock);
  Py_END_ALLOW_THREADS
  return rc;
}

static PyObject *renderer_build(Renderer *self, PyObject *Py_UNUSED(ignored))
{
  sl_error err = {0};
  if (renderer_build_unlocked(self, &err)) return raise_sl_error(&err);
  Py_RETURN_NONE;
}

static PyObject *vector3(const double v[3]) { return Py_BuildValue("(ddd)", v[0], v[1], v[2]); }

static PyObject *bytes_of(const float *values, size_t count)
{
  return PyBytes_FromStringAndSize((const char *)values, (Py_ssize_t)(count * sizeof(float)));
}

/* A frame as a dict: width, height, rgba/depth/transparency as bytes of float32 (rows from the
 * top), the camera, the sun's direction and the seconds it took. */
static PyObject *frame_dict(const sl_image *frame, const sl_camera *cam, const double sun[3], double seconds)
{
  const size_t n = (size_t)frame->width * frame->height;
  PyObject *camera = Py_BuildValue("{s:N,s:N,s:N,s:d}", "position", vector3(cam->position), "target",
                                   vector3(cam->target), "up", vector3(cam->up), "fov", cam->fov_deg);
  return camera ? Py_BuildValue("{s:i,s:i,s:N,s:N,s:N,s:N,s:N,s:d}", "width", frame->width, "height", frame->height,
                                "rgba", bytes_of(frame->rgba, 4 * n), "depth", bytes_of(frame->depth, n),
                                "transparency", bytes_of(frame->transparency, n), "camera", camera,
                                "sun_direction", vector3(sun), "seconds", seconds)
                : NULL;
}

/* render(threads=0) -> dict: the frame as render --cpu-composite draws it (sl_scene_render_frame):
 * width, height, rgba/depth/transparency as bytes of float32 (rows from the top), the camera and
 * the sun's direction (toward the sun, in the grid's axes) and the time it took. */
static PyObject *renderer_render(Renderer *self, PyObject *args, PyObject *kwargs)
{
  static char *keywords[] = {"threads", NULL};
  int threads = 0;
  if (!PyArg_ParseTupleAndKeywords(args, kwargs, "|i", keywords, &threads)) return NULL;
  if (threads < 0) {
    PyErr_SetString(PyExc_ValueError, "threads must be >= 0 (0: the default)");
    return NULL;
  }
  if (!threads) threads = self->settings->threads > 0 ? self->settings->threads : default_threads;
  sl_error err = {0};
  sl_camera cam;
  sl_image frame = {0};
  sl_render_stats stats = {0};
  double sun[3] = {0, 0, 0}, seconds = 0.0;
  int rc;
  Py_BEGIN_ALLOW_THREADS
  PyThread_acquire_lock(self->lock, WAIT_LOCK);
  omp_set_num_threads(threads); /* this thread's teams only */
  const double t0 = omp_get_wtime();
  rc = renderer_ensure_built(self, &err);
  if (!rc) rc = sl_scene_render_frame(self->settings, self->built, &cam, &frame, &stats, &err);
  if (!rc) memcpy(sun, self->built->scene.sun_direction, sizeof sun);
  seconds = omp_get_wtime() - t0;
  PyThread_release_lock(self->lock);
  Py_END_ALLOW_THREADS
  if (rc) return raise_sl_error(&err);
  PyObject *out = frame_dict(&frame, &cam, sun, seconds);
  sl_image_free(&frame);
  PyObject *slices = out ? PyLong_FromLong(stats.slices) : NULL;
  if (out && (!slices || PyDict_SetItemString(out, "slices", slices) ||
              PyDict_SetItemString(out, "night", stats.night ? Py_True : Py_False)))
    Py_CLEAR(out);
  Py_XDECREF(slices);
  return out;
}

/* reference(spp, seed=1, skylight=False, threads=0) -> dict: the same frame by the Monte Carlo
 * reference (sl_scene_reference_frame), with "stderr" (3 float32 per pixel: each channel's
 * standard error). */
static PyObject *renderer_reference(Renderer *self, PyObject *args, PyObject *kwargs)
{
  static char *keywords[] = {"spp", "seed", "skylight", "threads", NULL};
  long spp;
  unsigned long long seed = 1;
  int skylight = 0, threads = 0;
  if (!PyArg_ParseTupleAndKeywords(args, kwargs, "l|Kpi", keywords, &spp, &seed, &skylight, &threads)) return NULL;
  if (spp < 1 || threads < 0) {
    PyErr_SetString(PyExc_ValueError, "spp must be >= 1 and threads >= 0");
    return NULL;
  }
  if (!threads) threads = self->settings->threads > 0 ? self->settings->threads : default_threads;
  sl_error err = {0};
  sl_camera cam;
  sl_image frame = {0};
  float *se = NULL;
  double sun[3] = {0, 0, 0}, seconds = 0.0;
  int rc;
  Py_BEGIN_ALLOW_THREADS
  PyThread_acquire_lock(self->lock, WAIT_LOCK);
  omp_set_num_threads(threads);
  const double t0 = omp_get_wtime();
  rc = renderer_ensure_built(self, &err);
  if (!rc) {
    se = malloc((size_t)self->settings->width * self->settings->height * 3 * sizeof *se);
    rc = se ? sl_scene_reference_frame(self->settings, self->built, spp, seed, skylight, &cam, &frame, se, &err)
            : sl_fail(&err, SL_ERR_NOMEM, "reference: out of memory");
  }
  if (!rc) memcpy(sun, self->built->scene.sun_direction, sizeof sun);
  seconds = omp_get_wtime() - t0;
  PyThread_release_lock(self->lock);
  Py_END_ALLOW_THREADS
  PyObject *out = rc ? raise_sl_error(&err) : frame_dict(&frame, &cam, sun, seconds);
  if (out) {
    PyObject *b = bytes_of(se, (size_t)frame.width * frame.height * 3);
    if (!b || PyDict_SetItemString(out, "stderr", b)) Py_CLEAR(out);
    Py_XDECREF(b);
  }
  free(se);
  sl_image_free(&frame);
  return out;
}

/* The storm and sun the built scene holds (builds it first). */
static PyObject *renderer_placement(Renderer *self, PyObject *Py_UNUSED(ignored))
{
  sl_error err = {0};
  if (renderer_build_unlocked(self, &err)) return raise_sl_error(&err);
  const sl_built_scene *b = self->built;
  const sl_volume *v = &b->frame.volume;
  return Py_BuildValue("{s:d,s:d,s:(iii),s:(ddd),s:(ddd),s:d,s:d,s:d}", "sun_elevation", b->sun_elevation_deg,
                       "sun_azimuth", b->sun_azimuth_deg, "shape", v->nx, v->ny, v->nz, "origin", v->origin[0],
                       v->origin[1], v->origin[2], "spacing", v->spacing[0], v->spacing[1], v->spacing[2],
                       "center_lat", b->frame.center_lat, "center_lon", b->frame.center_lon, "load_seconds",
                       b->load_seconds);
}

static PyObject *renderer_close(Renderer *self, PyObject *Py_UNUSED(ignored))
{
  Py_BEGIN_ALLOW_THREADS
  PyThread_acquire_lock(self->lock, WAIT_LOCK);
  renderer_release(self);
  PyThread_release_lock(self->lock);
  Py_END_ALLOW_THREADS
  Py_RETURN_NONE;
}

static PyObject *renderer_get_built(Renderer *self, void *Py_UNUSED(closure)) { return PyBool_FromLong(self->built != NULL); }

static PyMethodDef renderer_methods[] = {
    {"build", (PyCFunction)renderer_build, METH_NOARGS, "Loads the storm and builds air, tables and renderer."},
    {"render", (PyCFunction)(void (*)(void))renderer_render, METH_VARARGS | METH_KEYWORDS,
     "render(threads=0) -> dict: one frame (bytes of float32) and its camera."},
    {"reference", (PyCFunction)(void (*)(void))renderer_reference, METH_VARARGS | METH_KEYWORDS,
     "reference(spp, seed=1, skylight=False, threads=0) -> dict: the Monte Carlo reference's frame."},
    {"placement", (PyCFunction)renderer_placement, METH_NOARGS, "The grid and the sun of the built scene."},
    {"close", (PyCFunction)renderer_close, METH_NOARGS, "Frees the built scene (it is built again on use)."},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef renderer_getset[] = {{"built", (getter)renderer_get_built, NULL, "Whether the scene is built.", NULL},
                                        {NULL, NULL, NULL, NULL, NULL}};

static PyTypeObject RendererType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "stormlight._stormlight.Renderer",
    .tp_basicsize = sizeof(Renderer),
    .tp_dealloc = (destructor)renderer_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Renderer(args): one scene of `stormlight render` arguments, built on first use.",
    .tp_methods = renderer_methods,
    .tp_getset = renderer_getset,
    .tp_init = (initproc)renderer_init,
    .tp_new = PyType_GenericNew,
};

/* ---- Module functions ---- */

static const char *option_type_name(sl_option_type t)
{
  switch (t) {
  case SL_OPTION_FLAG: return "flag";
  case SL_OPTION_INT: return "int";
  case SL_OPTION_NUMBER: return "number";
  case SL_OPTION_CHOICE: return "choice";
  case SL_OPTION_LIST: return "list";
  case SL_OPTION_TEXT: return "text";
  default: return "special";
  }
}

/* options() -> list of dicts: the option table (scene/sl_settings.h) the package's Scene takes its
 * keywords, their checks and their documentation from. */
static PyObject *module_options(PyObject *Py_UNUSED(module), PyObject *Py_UNUSED(ignored))
{
  PyObject *list = PyList_New(0);
  for (int i = 0; list && i < sl_settings_option_count; ++i) {
    const sl_option *o = &sl_settings_options[i];
    PyObject *d = Py_BuildValue("{s:s,s:s,s:z,s:z,s:s,s:z,s:d,s:d}", "name", o->name, "type",
                                option_type_name(o->type), "metavar", o->metavar, "default", o->fallback, "help",
                                o->help, "choices", o->choices, "min", o->min, "max", o->max);
    if (!d || PyList_Append(list, d)) Py_CLEAR(list);
    Py_XDECREF(d);
  }
  return list;
}

/* An image over caller-owned buffers (read-only use). */
static int image_from_buffers(Py_buffer *rgba, Py_buffer *depth, Py_buffer *transparency, int width, int height,
                              sl_image *img)
{
  const size_t n = (size_t)width * height;
  if (width <= 0 || height <= 0 || (size_t)rgba->len != 4 * n * sizeof(float) ||
      (depth && (size_t)depth->len != n * sizeof(float)) ||
      (transparency && (size_t)transparency->len != n * sizeof(float))) {
    PyErr_SetString(PyExc_ValueError, "the image buffers do not hold width x height float32 pixels");
    return -1;
  }
  img->width = width, img->height = height;
  img->rgba = rgba->buf;
  img->depth = depth ? depth->buf : NULL;
  img->transparency = transparency ? transparency->buf : NULL;
  return 0;
}

/* write_exr(path, width, height, rgba, depth, float32=False, sun_direction=None): linear HDR
 * RGBA plus Z, as render writes it (half floats unless float32). */
static PyObject *module_write_exr(PyObject *Py_UNUSED(module), PyObject *args, PyObject *kwargs)
{
  static char *keywords[] = {"path", "width", "height", "rgba", "depth", "float32", NULL};
  const char *path;
  int width, height, full = 0;
  Py_buffer rgba = {0}, depth = {0};
  if (!PyArg_ParseTupleAndKeywords(args, kwargs, "siiy*y*|p", keywords, &path, &width, &height, &rgba, &depth, &full))
    return NULL;
  sl_image img;
  PyObject *out = NULL;
  if (!image_from_buffers(&rgba, &depth, NULL, width, height, &img)) {
    sl_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = sl_write_exr(path, &img, full ? SL_EXR_FLOAT : SL_EXR_HALF, &err);
    Py_END_ALLOW_THREADS
    out = rc ? raise_sl_error(&err) : Py_NewRef(Py_None);
  }
  PyBuffer_Release(&rgba);
  PyBuffer_Release(&depth);
  return out;
}

/* write_png(path, width, height, rgba, exposure): tone-mapped sRGB as render writes it. */
static PyObject *module_write_png(PyObject *Py_UNUSED(module), PyObject *args, PyObject *kwargs)
{
  static char *keywords[] = {"path", "width", "height", "rgba", "exposure", NULL};
  const char *path;
  int width, height;
  double exposure;
  Py_buffer rgba = {0};
  if (!PyArg_ParseTupleAndKeywords(args, kwargs, "siiy*d", keywords, &path, &width, &height, &rgba, &exposure))
    return NULL;
  sl_image img;
  PyObject *out = NULL;
  if (!image_from_buffers(&rgba, NULL, NULL, width, height, &img)) {
    sl_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = sl_write_png(path, &img, (float)exposure, &err);
    Py_END_ALLOW_THREADS
    out = rc ? raise_sl_error(&err) : Py_NewRef(Py_None);
  }
  PyBuffer_Release(&rgba);
  return out;
}

/* scene_args(path) -> list of str: a scene file (docs/SCENES.md) as render's arguments, read by the
 * C reader every front end uses (sl_scene_file_args): the storm file first, relative to the
 * scene's folder, then "--key value" pairs. */
static PyObject *module_scene_args(PyObject *Py_UNUSED(module), PyObject *args)
{
  PyObject *path_obj;
  if (!PyArg_ParseTuple(args, "O&", PyUnicode_FSConverter, &path_obj)) return NULL;
  sl_scene_args a;
  sl_error err = {0};
  const int rc = sl_scene_file_args(PyBytes_AS_STRING(path_obj), &a, &err);
  Py_DECREF(path_obj);
  if (rc) return raise_sl_error(&err);
  PyObject *list = PyList_New(a.argc);
  for (int i = 0; list && i < a.argc; ++i) {
    PyObject *s = PyUnicode_DecodeFSDefault(a.argv[i]);
    if (!s) Py_CLEAR(list);
    else PyList_SET_ITEM(list, i, s);
  }
  sl_scene_args_free(&a);
  return list;
}

/* read_exr(path) -> dict: an EXR's width, height, rgba and depth (bytes of float32, rows from the
 * top), as sl_read_exr reads render's frames (A = the volume's coverage, Z its depth). */
static PyObject *module_read_exr(PyObject *Py_UNUSED(module), PyObject *args)
{
  PyObject *path_obj;
  if (!PyArg_ParseTuple(args, "O&", PyUnicode_FSConverter, &path_obj)) return NULL;
  sl_image img = {0};
  sl_error err = {0};
  int rc;
  Py_BEGIN_ALLOW_THREADS
  rc = sl_read_exr(PyBytes_AS_STRING(path_obj), &img, &err);
  Py_END_ALLOW_THREADS
  Py_DECREF(path_obj);
  if (rc) return raise_sl_error(&err);
  const size_t n = (size_t)img.width * img.height;
  PyObject *out = Py_BuildValue("{s:i,s:i,s:N,s:N}", "width", img.width, "height", img.height, "rgba",
                                bytes_of(img.rgba, 4 * n), "depth", bytes_of(img.depth, n));
  sl_image_free(&img);
  return out;
}

static PyObject *double_list(const double *v, int n)
{
  PyObject *list = PyList_New(n);
  for (int i = 0; list && i < n; ++i) {
    PyObject *x = PyFloat_FromDouble(v[i]);
    if (!x) Py_CLEAR(list);
    else PyList_SET_ITEM(list, i, x);
  }
  return list;
}

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
static PyObject *module_storm_info(PyObject *Py_UNUSED(module), PyObject *args)
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
    return raise_sl_error(&err);
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
  const char *kind = info->kind == SL_STORM_WRF ? "WRF" : info->kind == SL_STORM_CM1 ? "CM1" : "CF";
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

/* compare(width, height, a, b) -> dict: sl_image_compare of two RGBA buffers (b the reference), the
 * metrics of `stormlight compare`. */
static PyObject *module_compare(PyObject *Py_UNUSED(module), PyObject *args)
{
  int width, height;
  Py_buffer a = {0}, b = {0};
  if (!PyArg_ParseTuple(args, "iiy*y*", &width, &height, &a, &b)) return NULL;
  sl_image ia, ib;
  PyObject *out = NULL;
  if (!image_from_buffers(&a, NULL, NULL, width, height, &ia) && !image_from_buffers(&b, NULL, NULL, width, height, &ib)) {
    sl_image_metrics m;
    sl_error err = {0};
    if (sl_image_compare(&ia, &ib, &m, &err)) out = raise_sl_error(&err);
    else
      out = Py_BuildValue("{s:d,s:d,s:d,s:l}", "relative_rmse", m.relative_rmse, "max_abs_diff", m.max_abs_diff,
                          "psnr_db", m.psnr_db, "nonfinite_pixels", m.nonfinite);
  }
  PyBuffer_Release(&a);
  PyBuffer_Release(&b);
  return out;
}

/* sun_position(iso8601, lat, lon) -> dict: the sun's apparent position (sl_solar_position_compute,
 * with refraction, as `stormlight sun`). */
static PyObject *module_sun_position(PyObject *Py_UNUSED(module), PyObject *args)
{
  const char *when;
  double lat, lon;
  if (!PyArg_ParseTuple(args, "sdd", &when, &lat, &lon)) return NULL;
  sl_utc t;
  sl_solar_position p;
  sl_error err = {0};
  if (sl_utc_parse_iso8601(when, &t, &err) || sl_solar_position_compute(&t, lat, lon, NULL, &p, &err))
    return raise_sl_error(&err);
  return Py_BuildValue("{s:d,s:d,s:d,s:d,s:d,s:d,s:d,s:N,s:O}", "elevation", p.elevation_deg, "azimuth",
                       p.azimuth_deg, "zenith", p.zenith_deg, "elevation_true", p.elevation_true_deg, "declination",
                       p.declination_deg, "hour_angle", p.hour_angle_deg, "julian_day", p.julian_day, "direction",
                       vector3(p.direction), "night", p.night ? Py_True : Py_False);
}

/* optics(particle, wavelength_nm, angles_rad, order) -> dict: the particle type's table at one
 * wavelength (built by render/optics, or read from its on-disk cache): extinction cross-section,
 * albedo, asymmetry, the truncated forward fraction f, the forward fractions F_n, and the smooth
 * part of Ams_order at the given angles (bytes of float64, 1/sr; the forward Dirac of weight f^n
 * is apart). */
static PyObject *module_optics(PyObject *Py_UNUSED(module), PyObject *args)
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
      raise_sl_error(&err);
    } else if (order > t->max_order) {
      PyErr_Format(PyExc_ValueError, "order %d is past the table's last order %d (isotropic from there)", order,
                   t->max_order);
    } else {
      const double *theta = angles.buf;
      for (size_t i = 0; i < n; ++i) {
        const double a = theta[i] < 0.0 ? 0.0 : theta[i] > M_PI ? M_PI : theta[i];
        values[i] = sl_phase_table_ams_theta(t, order, a);
      }
      PyObject *forward = double_list(t->forward, t->max_order + 1);
      out = forward ? Py_BuildValue("{s:d,s:d,s:d,s:d,s:d,s:i,s:N,s:N}", "wavelength", t->wavelength_nm, "sigma_ext",
                                    t->sigma_ext, "albedo", t->albedo, "asymmetry", t->asymmetry, "truncated_fraction",
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
static PyObject *module_sky(PyObject *Py_UNUSED(module), PyObject *args)
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
    return raise_sl_error(&err);
  return Py_BuildValue("{s:N,s:N,s:d,s:N,s:N,s:N,s:O}", "wavelengths_nm", double_list(atm.wavelength_nm, count),
                       "beta_sea_level", double_list(atm.beta_sea_level, count), "scale_height_m", atm.scale_height,
                       "radiance", double_list(radiance, count), "transparency", double_list(transparency, count),
                       "sunlight_at_eye", double_list(sunlight, count), "night", night ? Py_True : Py_False);
}

static PyObject *module_version(PyObject *Py_UNUSED(module), PyObject *Py_UNUSED(ignored))
{
  return PyUnicode_FromString(sl_version());
}

static PyMethodDef module_methods[] = {
    {"options", module_options, METH_NOARGS, "The option table: name, type, default, help, range, choices."},
    {"write_exr", (PyCFunction)(void (*)(void))module_write_exr, METH_VARARGS | METH_KEYWORDS,
     "write_exr(path, width, height, rgba, depth, float32=False)"},
    {"write_png", (PyCFunction)(void (*)(void))module_write_png, METH_VARARGS | METH_KEYWORDS,
     "write_png(path, width, height, rgba, exposure)"},
    {"scene_args", module_scene_args, METH_VARARGS, "scene_args(path) -> a scene file as render's arguments."},
    {"read_exr", module_read_exr, METH_VARARGS, "read_exr(path) -> dict of an EXR frame's buffers."},
    {"storm_info", module_storm_info, METH_VARARGS, "storm_info(path) -> what a storm file holds."},
    {"compare", module_compare, METH_VARARGS, "compare(width, height, a, b) -> the metrics of stormlight compare."},
    {"sun_position", module_sun_position, METH_VARARGS, "sun_position(iso8601, lat, lon) -> the sun's position."},
    {"optics", module_optics, METH_VARARGS, "optics(particle, wavelength_nm, angles_rad, order) -> a table's values."},
    {"sky", module_sky, METH_VARARGS, "sky(eye_height, view_el, view_az, sun_el, sun_az, distance, round, spectral)"},
    {"version", module_version, METH_NOARGS, "libstormlight's version."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {PyModuleDef_HEAD_INIT, "_stormlight",
                                        "The C extension of the stormlight package (libstormlight).", -1,
                                        module_methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__stormlight(void)
{
  default_threads = omp_get_max_threads();
  if (PyType_Ready(&RendererType) < 0) return NULL;
  PyObject *m = PyModule_Create(&module_def);
  if (!m) return NULL;
  Py_INCREF(&RendererType);
  if (PyModule_AddObject(m, "Renderer", (PyObject *)&RendererType) < 0) {
    Py_DECREF(&RendererType);
    Py_DECREF(m);
    return NULL;
  }
  return m;
}
