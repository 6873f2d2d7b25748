/* What the files of stormlight._stormlight share (python/src): the CPython API and libstormlight,
 * the error mapping, the Renderer type and the module functions each file defines. Only the
 * CPython API and the buffer protocol: frames leave as bytes that the package wraps in numpy
 * arrays without a copy (numpy.frombuffer), so the extension does not depend on numpy's C API. */
#ifndef SLPY_EXTENSION_H
#define SLPY_EXTENSION_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include "stormlight.h"

/* module.c */
extern int slpy_default_threads; /* OpenMP threads of a render that asks for none: the default at import */
PyObject *slpy_raise(const sl_error *err); /* the error as OSError, ValueError, MemoryError or RuntimeError */
PyObject *slpy_vector3(const double v[3]);
PyObject *slpy_bytes(const float *values, size_t count);
PyObject *slpy_double_list(const double *v, int n);
/* Settings from a sequence of str (render's arguments: the storm file, "--option value" pairs): the
 * defaults, then the option table's parser, then (check) sl_settings_check; -1 with the exception
 * set. */
int slpy_settings_from_args(PyObject *args, sl_settings *s, int check);

/* renderer.c */
extern PyTypeObject slpy_renderer_type;

/* images.c */
int slpy_image_from_buffers(Py_buffer *rgba, Py_buffer *depth, Py_buffer *transparency, int width, int height,
                            sl_image *img);
PyObject *slpy_write_exr(PyObject *module, PyObject *args, PyObject *kwargs);
PyObject *slpy_write_png(PyObject *module, PyObject *args, PyObject *kwargs);
PyObject *slpy_read_exr(PyObject *module, PyObject *args);
PyObject *slpy_compare(PyObject *module, PyObject *args);
PyObject *slpy_srgb8(PyObject *module, PyObject *args);

/* numbers.c */
PyObject *slpy_storm_info(PyObject *module, PyObject *args);
PyObject *slpy_info_json(PyObject *module, PyObject *args);
PyObject *slpy_sun_position(PyObject *module, PyObject *args);
PyObject *slpy_optics(PyObject *module, PyObject *args);
PyObject *slpy_sky(PyObject *module, PyObject *args);

#endif
