/* stormlight._stormlight.Renderer: one scene's settings and, once built, its storm, air, tables
 * and CPU renderer; building and rendering release the GIL and take the renderer's lock. */
#include "extension.h"

#include <omp.h>
#include <pythread.h>
#include <stdlib.h>
#include <string.h>

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
  renderer_release(self);
  if (!self->settings) self->settings = malloc(sizeof *self->settings);
  if (!self->lock) self->lock = PyThread_allocate_lock();
  if (!self->settings || !self->lock) {
    PyErr_NoMemory();
    return -1;
  }
  return slpy_settings_from_args(list, self->settings, 1);
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

static PyObject *renderer_build(Renderer *self, PyObject *Py_UNUSED(ignored))
{
  sl_error err = {0};
  int rc;
  Py_BEGIN_ALLOW_THREADS
  PyThread_acquire_lock(self->lock, WAIT_LOCK);
  rc = renderer_ensure_built(self, &err);
  PyThread_release_lock(self->lock);
  Py_END_ALLOW_THREADS
  if (rc) return slpy_raise(&err);
  Py_RETURN_NONE;
}

/* A frame as a dict: width, height, rgba/depth/transparency as bytes of float32 (rows from the
 * top), the camera, the sun's direction and the seconds it took. */
static PyObject *frame_dict(const sl_image *frame, const sl_camera *cam, const double sun[3], double seconds)
{
  const size_t n = (size_t)frame->width * frame->height;
  PyObject *camera = Py_BuildValue("{s:N,s:N,s:N,s:d}", "position", slpy_vector3(cam->position), "target",
                                   slpy_vector3(cam->target), "up", slpy_vector3(cam->up), "fov", cam->fov_deg);
  return camera ? Py_BuildValue("{s:i,s:i,s:N,s:N,s:N,s:N,s:N,s:d}", "width", frame->width, "height", frame->height,
                                "rgba", slpy_bytes(frame->rgba, 4 * n), "depth", slpy_bytes(frame->depth, n),
                                "transparency", slpy_bytes(frame->transparency, n), "camera", camera,
                                "sun_direction", slpy_vector3(sun), "seconds", seconds)
                : NULL;
}

/* A frame drawer: the fast renderer's or the reference's, given the built scene. */
typedef int (*frame_drawer)(Renderer *self, void *how, sl_camera *cam, sl_image *frame, sl_error *err);

/* draw's frame with the GIL released and the lock held, on `threads` OpenMP threads of this
 * thread's teams (0: the scene's threads, else the default), the scene built first if it is not;
 * the sun's direction and the seconds taken with it. */
static int renderer_frame(Renderer *self, int threads, frame_drawer draw, void *how, sl_camera *cam, sl_image *frame,
                          double sun[3], double *seconds, sl_error *err)
{
  if (!threads) threads = self->settings->threads > 0 ? self->settings->threads : slpy_default_threads;
  int rc;
  Py_BEGIN_ALLOW_THREADS
  PyThread_acquire_lock(self->lock, WAIT_LOCK);
  omp_set_num_threads(threads);
  const double t0 = omp_get_wtime();
  rc = renderer_ensure_built(self, err);
  if (!rc) rc = draw(self, how, cam, frame, err);
  if (!rc) memcpy(sun, self->built->scene.sun_direction, 3 * sizeof *sun);
  *seconds = omp_get_wtime() - t0;
  PyThread_release_lock(self->lock);
  Py_END_ALLOW_THREADS
  return rc;
}

static int draw_fast(Renderer *self, void *stats, sl_camera *cam, sl_image *frame, sl_error *err)
{
  return sl_scene_render_frame(self->settings, self->built, cam, frame, stats, err);
}

typedef struct reference_request {
  long spp;
  unsigned long long seed;
  int skylight;
  float *stderr_rgb;
} reference_request;

static int draw_reference(Renderer *self, void *how, sl_camera *cam, sl_image *frame, sl_error *err)
{
  const reference_request *q = how;
  return sl_scene_reference_frame(self->settings, self->built, q->spp, q->seed, q->skylight, cam, frame, q->stderr_rgb,
                                  err);
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
  sl_error err = {0};
  sl_camera cam;
  sl_image frame = {0};
  sl_render_stats stats = {0};
  double sun[3] = {0, 0, 0}, seconds = 0.0;
  if (renderer_frame(self, threads, draw_fast, &stats, &cam, &frame, sun, &seconds, &err)) return slpy_raise(&err);
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
  reference_request q = {.seed = 1};
  int threads = 0;
  if (!PyArg_ParseTupleAndKeywords(args, kwargs, "l|Kpi", keywords, &q.spp, &q.seed, &q.skylight, &threads))
    return NULL;
  if (q.spp < 1 || threads < 0) {
    PyErr_SetString(PyExc_ValueError, "spp must be >= 1 and threads >= 0");
    return NULL;
  }
  /* The camera's size is the settings' (sl_scene_camera). */
  q.stderr_rgb = malloc((size_t)self->settings->width * self->settings->height * 3 * sizeof *q.stderr_rgb);
  if (!q.stderr_rgb) return PyErr_NoMemory();
  sl_error err = {0};
  sl_camera cam;
  sl_image frame = {0};
  double sun[3] = {0, 0, 0}, seconds = 0.0;
  PyObject *out = renderer_frame(self, threads, draw_reference, &q, &cam, &frame, sun, &seconds, &err)
                      ? slpy_raise(&err)
                      : frame_dict(&frame, &cam, sun, seconds);
  if (out) {
    PyObject *b = slpy_bytes(q.stderr_rgb, (size_t)frame.width * frame.height * 3);
    if (!b || PyDict_SetItemString(out, "stderr", b)) Py_CLEAR(out);
    Py_XDECREF(b);
  }
  free(q.stderr_rgb);
  sl_image_free(&frame);
  return out;
}

/* The storm and sun the built scene holds (builds it first). */
static PyObject *renderer_placement(Renderer *self, PyObject *Py_UNUSED(ignored))
{
  sl_error err = {0};
  sl_built_scene b; /* the fields read, copied under the lock (another thread may close it) */
  int rc;
  Py_BEGIN_ALLOW_THREADS
  PyThread_acquire_lock(self->lock, WAIT_LOCK);
  rc = renderer_ensure_built(self, &err);
  if (!rc) memcpy(&b, self->built, sizeof b);
  PyThread_release_lock(self->lock);
  Py_END_ALLOW_THREADS
  if (rc) return slpy_raise(&err);
  const sl_volume *v = &b.frame.volume;
  return Py_BuildValue("{s:d,s:d,s:(iii),s:(ddd),s:(ddd),s:d,s:d,s:d}", "sun_elevation", b.sun_elevation_deg,
                       "sun_azimuth", b.sun_azimuth_deg, "shape", v->nx, v->ny, v->nz, "origin", v->origin[0],
                       v->origin[1], v->origin[2], "spacing", v->spacing[0], v->spacing[1], v->spacing[2],
                       "center_lat", b.frame.center_lat, "center_lon", b.frame.center_lon, "load_seconds",
                       b.load_seconds);
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

PyTypeObject slpy_renderer_type = {
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

