/* Frames in and out of the extension: EXR and PNG through io/, and the metrics of `stormlight
 * compare`, over caller-owned buffers (the buffer protocol). */
#include "extension.h"

/* An image over caller-owned buffers (read-only use). */
int slpy_image_from_buffers(Py_buffer *rgba, Py_buffer *depth, Py_buffer *transparency, int width, int height,
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
PyObject *slpy_write_exr(PyObject *Py_UNUSED(module), PyObject *args, PyObject *kwargs)
{
  static char *keywords[] = {"path", "width", "height", "rgba", "depth", "float32", NULL};
  const char *path;
  int width, height, full = 0;
  Py_buffer rgba = {0}, depth = {0};
  if (!PyArg_ParseTupleAndKeywords(args, kwargs, "siiy*y*|p", keywords, &path, &width, &height, &rgba, &depth, &full))
    return NULL;
  sl_image img;
  PyObject *out = NULL;
  if (!slpy_image_from_buffers(&rgba, &depth, NULL, width, height, &img)) {
    sl_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = sl_write_exr(path, &img, full ? SL_EXR_FLOAT : SL_EXR_HALF, &err);
    Py_END_ALLOW_THREADS
    out = rc ? slpy_raise(&err) : Py_NewRef(Py_None);
  }
  PyBuffer_Release(&rgba);
  PyBuffer_Release(&depth);
  return out;
}

/* write_png(path, width, height, rgba, exposure): tone-mapped sRGB as render writes it. */
PyObject *slpy_write_png(PyObject *Py_UNUSED(module), PyObject *args, PyObject *kwargs)
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
  if (!slpy_image_from_buffers(&rgba, NULL, NULL, width, height, &img)) {
    sl_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = sl_write_png(path, &img, (float)exposure, &err);
    Py_END_ALLOW_THREADS
    out = rc ? slpy_raise(&err) : Py_NewRef(Py_None);
  }
  PyBuffer_Release(&rgba);
  return out;
}

/* srgb8(width, height, rgba, exposure) -> bytes: the tone-mapped 8-bit sRGB render's PNGs hold. */
PyObject *slpy_srgb8(PyObject *Py_UNUSED(module), PyObject *args)
{
  int width, height;
  double exposure;
  Py_buffer rgba = {0};
  if (!PyArg_ParseTuple(args, "iiy*d", &width, &height, &rgba, &exposure)) return NULL;
  sl_image img;
  PyObject *out = NULL;
  if (!slpy_image_from_buffers(&rgba, NULL, NULL, width, height, &img)) {
    out = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)width * height * 3);
    if (out) sl_image_to_srgb8(&img, (float)exposure, (unsigned char *)PyBytes_AS_STRING(out));
  }
  PyBuffer_Release(&rgba);
  return out;
}

/* read_exr(path) -> dict: an EXR's width, height, rgba and depth (bytes of float32, rows from the
 * top), as sl_read_exr reads render's frames (A = the volume's coverage, Z its depth). */
PyObject *slpy_read_exr(PyObject *Py_UNUSED(module), PyObject *args)
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
  if (rc) return slpy_raise(&err);
  const size_t n = (size_t)img.width * img.height;
  PyObject *out = Py_BuildValue("{s:i,s:i,s:N,s:N}", "width", img.width, "height", img.height, "rgba",
                                slpy_bytes(img.rgba, 4 * n), "depth", slpy_bytes(img.depth, n));
  sl_image_free(&img);
  return out;
}

/* compare(width, height, a, b) -> dict: sl_image_compare of two RGBA buffers (b the reference), the
 * metrics of `stormlight compare`. */
PyObject *slpy_compare(PyObject *Py_UNUSED(module), PyObject *args)
{
  int width, height;
  Py_buffer a = {0}, b = {0};
  if (!PyArg_ParseTuple(args, "iiy*y*", &width, &height, &a, &b)) return NULL;
  sl_image ia, ib;
  PyObject *out = NULL;
  if (!slpy_image_from_buffers(&a, NULL, NULL, width, height, &ia) && !slpy_image_from_buffers(&b, NULL, NULL, width, height, &ib)) {
    sl_image_metrics m;
    sl_error err = {0};
    if (sl_image_compare(&ia, &ib, &m, &err)) out = slpy_raise(&err);
    else
      out = Py_BuildValue("{s:d,s:d,s:d,s:l}", "relative_rmse", m.relative_rmse, "max_abs_diff", m.max_abs_diff,
                          "psnr_db", m.psnr_db, "nonfinite_pixels", m.nonfinite);
  }
  PyBuffer_Release(&a);
  PyBuffer_Release(&b);
  return out;
}

