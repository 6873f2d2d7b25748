/* stormlight._stormlight: the Python package's extension over libstormlight (scene/stormlight.h):
 * the module, its method table, the option table, scene files and what the other files share
 * (extension.h). A Renderer (renderer.c) holds one scene's settings and, once built, its storm,
 * air, tables and CPU renderer: plan once, render many. */
#include "extension.h"

#include <omp.h>

/* The OpenMP threads a render gets when it asks for none: the process's default at import (the
 * per-thread setting would otherwise keep the last render's). */
int slpy_default_threads = 1;

/* A one-line error as the exception its kind calls for. */
PyObject *slpy_raise(const sl_error *err)
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

PyObject *slpy_vector3(const double v[3]) { return Py_BuildValue("(ddd)", v[0], v[1], v[2]); }

PyObject *slpy_bytes(const float *values, size_t count)
{
  return PyBytes_FromStringAndSize((const char *)values, (Py_ssize_t)(count * sizeof(float)));
}

PyObject *slpy_double_list(const double *v, int n)
{
  PyObject *list = PyList_New(n);
  for (int i = 0; list && i < n; ++i) {
    PyObject *x = PyFloat_FromDouble(v[i]);
    if (!x) Py_CLEAR(list);
    else PyList_SET_ITEM(list, i, x);
  }
  return list;
}

int slpy_settings_from_args(PyObject *args, sl_settings *s, int check)
{
  PyObject *seq = PySequence_Fast(args, "args must be a sequence of str");
  if (!seq) return -1;
  const Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
  char **argv = calloc((size_t)n + 1, sizeof *argv);
  int rc = 0;
  if (!argv) PyErr_NoMemory(), rc = -1;
  for (Py_ssize_t i = 0; !rc && i < n; ++i) {
    PyObject *item = PySequence_Fast_GET_ITEM(seq, i);
    argv[i] = PyUnicode_Check(item) ? (char *)PyUnicode_AsUTF8(item) : NULL; /* kept alive by seq */
    if (!argv[i]) {
      if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "args must be a sequence of str");
      rc = -1;
    }
  }
  if (!rc) {
    sl_error err = {0};
    sl_settings_defaults(s);
    if (sl_settings_parse_args(s, (int)n, argv, &err) || (check && sl_settings_check(s, &err))) {
      slpy_raise(&err);
      rc = -1;
    }
  }
  free(argv);
  Py_DECREF(seq);
  return rc;
}

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
  if (rc) return slpy_raise(&err);
  PyObject *list = PyList_New(a.argc);
  for (int i = 0; list && i < a.argc; ++i) {
    PyObject *s = PyUnicode_DecodeFSDefault(a.argv[i]);
    if (!s) Py_CLEAR(list);
    else PyList_SET_ITEM(list, i, s);
  }
  sl_scene_args_free(&a);
  return list;
}

static PyObject *module_version(PyObject *Py_UNUSED(module), PyObject *Py_UNUSED(ignored))
{
  return PyUnicode_FromString(sl_version());
}

static PyMethodDef module_methods[] = {
    {"options", module_options, METH_NOARGS, "The option table: name, type, default, help, range, choices."},
    {"write_exr", (PyCFunction)(void (*)(void))slpy_write_exr, METH_VARARGS | METH_KEYWORDS,
     "write_exr(path, width, height, rgba, depth, float32=False)"},
    {"write_png", (PyCFunction)(void (*)(void))slpy_write_png, METH_VARARGS | METH_KEYWORDS,
     "write_png(path, width, height, rgba, exposure)"},
    {"scene_args", module_scene_args, METH_VARARGS, "scene_args(path) -> a scene file as render's arguments."},
    {"read_exr", slpy_read_exr, METH_VARARGS, "read_exr(path) -> dict of an EXR frame's buffers."},
    {"storm_info", slpy_storm_info, METH_VARARGS, "storm_info(path) -> what a storm file holds."},
    {"srgb8", slpy_srgb8, METH_VARARGS, "srgb8(width, height, rgba, exposure) -> tone-mapped 8-bit sRGB."},
    {"info_json", slpy_info_json, METH_VARARGS, "info_json(args) -> stormlight info --json of a storm file."},
    {"compare", slpy_compare, METH_VARARGS, "compare(width, height, a, b) -> the metrics of stormlight compare."},
    {"sun_position", slpy_sun_position, METH_VARARGS, "sun_position(iso8601, lat, lon) -> the sun's position."},
    {"optics", slpy_optics, METH_VARARGS, "optics(particle, wavelength_nm, angles_rad, order) -> a table's values."},
    {"sky", slpy_sky, METH_VARARGS, "sky(eye_height, view_el, view_az, sun_el, sun_az, distance, round, spectral)"},
    {"version", module_version, METH_NOARGS, "libstormlight's version."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {PyModuleDef_HEAD_INIT, "_stormlight",
                                        "The C extension of the stormlight package (libstormlight).", -1,
                                        module_methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__stormlight(void)
{
  slpy_default_threads = omp_get_max_threads();
  if (PyType_Ready(&slpy_renderer_type) < 0) return NULL;
  PyObject *m = PyModule_Create(&module_def);
  if (!m) return NULL;
  Py_INCREF(&slpy_renderer_type);
  if (PyModule_AddObject(m, "Renderer", (PyObject *)&slpy_renderer_type) < 0) {
    Py_DECREF(&slpy_renderer_type);
    Py_DECREF(m);
    return NULL;
  }
  return m;
}
