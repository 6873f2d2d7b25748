#include <math.h>
#include <openexr.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sl_image_io.h"
#include "sl_tempfile.h"

/* ---- OpenEXR ---------------------------------------------------------------------------- */

static int exr_fail(sl_error *err, int code, const char *path, const char *what, exr_result_t r)
{
  return sl_fail(err, code, "%s: %s: %s", path, what, exr_get_default_error_message(r));
}

/* The user-side layout of one channel: a base pointer, its stride in bytes between pixels. */
typedef struct channel_source {
  const char *name;
  uint8_t *base;
  int pixel_stride;
} channel_source;

static const channel_source *find_channel(const channel_source *list, int n, const char *name)
{
  for (int i = 0; i < n; ++i)
    if (list[i].base && strcmp(list[i].name, name) == 0) return &list[i];
  return NULL;
}

static void silent_handler(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
  (void)ctxt;
  (void)code;
  (void)msg;
}

int sl_write_exr(const char *path, const sl_image *img, sl_exr_precision precision, sl_error *err)
{
  return sl_write_exr_meta(path, img, precision, NULL, err);
}

void sl_exr_camera_matrices(const double position[3], const double target[3], const double up[3], double fov_deg,
                            double aspect, double near_m, double far_m, sl_exr_metadata *meta)
{
  double f[3], r[3], u[3];
  double n = 0.0;
  for (int a = 0; a < 3; ++a) f[a] = target[a] - position[a], n += f[a] * f[a];
  n = sqrt(n);
  for (int a = 0; a < 3; ++a) f[a] /= n;
  r[0] = f[1] * up[2] - f[2] * up[1], r[1] = f[2] * up[0] - f[0] * up[2], r[2] = f[0] * up[1] - f[1] * up[0];
  n = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  for (int a = 0; a < 3; ++a) r[a] /= n;
  u[0] = r[1] * f[2] - r[2] * f[1], u[1] = r[2] * f[0] - r[0] * f[2], u[2] = r[0] * f[1] - r[1] * f[0];
  /* Camera axes as columns: x = right, y = up, z = back (-forward); translation in the last row. */
  double w2c[16] = {0};
  for (int i = 0; i < 3; ++i) {
    w2c[4 * i + 0] = r[i];
    w2c[4 * i + 1] = u[i];
    w2c[4 * i + 2] = -f[i];
  }
  w2c[12] = -(position[0] * r[0] + position[1] * r[1] + position[2] * r[2]);
  w2c[13] = -(position[0] * u[0] + position[1] * u[1] + position[2] * u[2]);
  w2c[14] = (position[0] * f[0] + position[1] * f[1] + position[2] * f[2]);
  w2c[15] = 1.0;
  /* The OpenGL perspective matrix, transposed for row vectors. */
  const double t = 1.0 / tan(0.5 * fov_deg * M_PI / 180.0);
  double proj[16] = {0};
  proj[0] = t / aspect;
  proj[5] = t;
  proj[10] = (far_m + near_m) / (near_m - far_m);
  proj[11] = -1.0;
  proj[14] = 2.0 * far_m * near_m / (near_m - far_m);
  meta->has_camera = 1;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      double v = 0.0;
      for (int k = 0; k < 4; ++k) v += w2c[4 * i + k] * proj[4 * k + j];
      meta->world_to_ndc[4 * i + j] = (float)v;
      meta->world_to_camera[4 * i + j] = (float)w2c[4 * i + j];
    }
}

int sl_write_exr_meta(const char *path, const sl_image *img, sl_exr_precision precision,
                      const sl_exr_metadata *meta, sl_error *err)
{
  char tmp[4096];
  if (sl_temp_name(path, tmp, sizeof tmp, err)) return err->code;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = silent_handler;
  exr_context_t ctx = NULL;
  int rc = SL_OK;
  exr_result_t r = exr_start_write(&ctx, tmp, EXR_WRITE_FILE_DIRECTLY, &init);
  if (r != EXR_ERR_SUCCESS) return exr_fail(err, SL_ERR_IO, path, "cannot create", r);
  int part = 0;
  const exr_pixel_type_t ctype = precision == SL_EXR_FLOAT ? EXR_PIXEL_FLOAT : EXR_PIXEL_HALF;
  const channel_source sources[] = {
      {"A", (uint8_t *)(img->rgba + 3), 16}, {"B", (uint8_t *)(img->rgba + 2), 16},
      {"G", (uint8_t *)(img->rgba + 1), 16}, {"R", (uint8_t *)(img->rgba + 0), 16},
      {"Z", (uint8_t *)img->depth, 4},
  };
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int enc_ready = 0;
  if ((r = exr_add_part(ctx, "main", EXR_STORAGE_SCANLINE, &part)) ||
      (r = exr_initialize_required_attr_simple(ctx, part, img->width, img->height, EXR_COMPRESSION_ZIP)))
    goto exr_error;
  for (int c = 0; c < 5; ++c) {
    if (!sources[c].base) continue;
    const exr_pixel_type_t t = sources[c].name[0] == 'Z' ? EXR_PIXEL_FLOAT : ctype;
    if ((r = exr_add_channel(ctx, part, sources[c].name, t, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1))) goto exr_error;
  }
  if (meta && meta->has_camera) {
    exr_attr_m44f_t m;
    memcpy(m.m, meta->world_to_camera, sizeof m.m);
    if ((r = exr_attr_set_m44f(ctx, part, "worldToCamera", &m))) goto exr_error;
    memcpy(m.m, meta->world_to_ndc, sizeof m.m);
    if ((r = exr_attr_set_m44f(ctx, part, "worldToNDC", &m))) goto exr_error;
  }
  if (meta && meta->has_sun) {
    exr_attr_v3f_t v;
    v.x = meta->sun_direction[0], v.y = meta->sun_direction[1], v.z = meta->sun_direction[2];
    if ((r = exr_attr_set_v3f(ctx, part, "sunDirection", &v))) goto exr_error;
  }
  if (meta && meta->scene && (r = exr_attr_set_string(ctx, part, "stormlightScene", meta->scene))) goto exr_error;
  if ((r = exr_write_header(ctx))) goto exr_error;
  int32_t lines = 1;
  if ((r = exr_get_scanlines_per_chunk(ctx, part, &lines))) goto exr_error;
  for (int y = 0; y < img->height; y += lines) {
    exr_chunk_info_t cinfo;
    if ((r = exr_write_scanline_chunk_info(ctx, part, y, &cinfo))) goto exr_error;
    r = enc_ready ? exr_encoding_update(ctx, part, &cinfo, &enc) : exr_encoding_initialize(ctx, part, &cinfo, &enc);
    if (r) goto exr_error;
    for (int c = 0; c < enc.channel_count; ++c) {
      const channel_source *s = find_channel(sources, 5, enc.channels[c].channel_name);
      exr_coding_channel_info_t *ch = &enc.channels[c];
      ch->user_data_type = EXR_PIXEL_FLOAT;
      ch->user_bytes_per_element = 4;
      ch->user_pixel_stride = s->pixel_stride;
      ch->user_line_stride = s->pixel_stride * img->width;
      ch->encode_from_ptr = s->base + (size_t)(cinfo.start_y) * (size_t)ch->user_line_stride;
    }
    if (!enc_ready) {
      if ((r = exr_encoding_choose_default_routines(ctx, part, &enc))) goto exr_error;
      enc_ready = 1;
    }
    if ((r = exr_encoding_run(ctx, part, &enc))) goto exr_error;
  }
  if (enc_ready) exr_encoding_destroy(ctx, &enc);
  if ((r = exr_finish(&ctx))) {
    unlink(tmp);
    return exr_fail(err, SL_ERR_IO, path, "cannot finish writing", r);
  }
  return sl_temp_commit(tmp, path, err);
exr_error:
  rc = exr_fail(err, SL_ERR_IO, path, "cannot write", r);
  if (enc_ready) exr_encoding_destroy(ctx, &enc);
  exr_finish(&ctx);
  unlink(tmp);
  return rc;
}

int sl_read_exr(const char *path, sl_image *img, sl_error *err)
{
  *img = (sl_image){0};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = silent_handler;
  exr_context_t ctx = NULL;
  exr_result_t r = exr_start_read(&ctx, path, &init);
  if (r != EXR_ERR_SUCCESS) {
    const int code = (r == EXR_ERR_FILE_ACCESS) ? SL_ERR_IO : SL_ERR_FORMAT;
    return exr_fail(err, code, path, code == SL_ERR_IO ? "cannot open" : "not a readable OpenEXR file", r);
  }
  int rc = SL_OK;
  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  int dec_ready = 0;
  exr_storage_t storage;
  exr_attr_box2i_t dw;
  if ((r = exr_get_storage(ctx, 0, &storage)) || (r = exr_get_data_window(ctx, 0, &dw))) goto exr_error;
  if (storage != EXR_STORAGE_SCANLINE) {
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: only scanline OpenEXR images are supported", path);
    goto done;
  }
  const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
  if ((rc = sl_image_alloc(img, w, h, err))) goto done;
  const exr_attr_chlist_t *chl = NULL;
  if ((r = exr_get_channels(ctx, 0, &chl))) goto exr_error;
  int have[5] = {0};
  const char *names = "ABGRZ";
  for (int c = 0; c < chl->num_channels; ++c)
    for (int k = 0; k < 5; ++k)
      if (strlen(chl->entries[c].name.str) == 1 && chl->entries[c].name.str[0] == names[k]) have[k] = 1;
  if (!have[1] || !have[2] || !have[3]) {
    rc = sl_fail(err, SL_ERR_FORMAT, "%s: the image has no R, G and B channels", path);
    goto done;
  }
  for (size_t i = 0; i < (size_t)w * h; ++i) {
    img->rgba[4 * i + 3] = 1.0f;
    img->depth[i] = INFINITY;
  }
  const channel_source sources[] = {
      {"A", (uint8_t *)(img->rgba + 3), 16}, {"B", (uint8_t *)(img->rgba + 2), 16},
      {"G", (uint8_t *)(img->rgba + 1), 16}, {"R", (uint8_t *)(img->rgba + 0), 16},
      {"Z", (uint8_t *)img->depth, 4},
  };
  int32_t lines = 1;
  if ((r = exr_get_scanlines_per_chunk(ctx, 0, &lines))) goto exr_error;
  for (int y = dw.min.y; y <= dw.max.y; y += lines) {
    exr_chunk_info_t cinfo;
    if ((r = exr_read_scanline_chunk_info(ctx, 0, y, &cinfo))) goto exr_error;
    r = dec_ready ? exr_decoding_update(ctx, 0, &cinfo, &dec) : exr_decoding_initialize(ctx, 0, &cinfo, &dec);
    if (r) goto exr_error;
    for (int c = 0; c < dec.channel_count; ++c) {
      exr_coding_channel_info_t *ch = &dec.channels[c];
      const channel_source *s = find_channel(sources, 5, ch->channel_name);
      if (!s || ch->x_samples != 1 || ch->y_samples != 1) {
        ch->decode_to_ptr = NULL;
        continue;
      }
      ch->user_data_type = EXR_PIXEL_FLOAT;
      ch->user_bytes_per_element = 4;
      ch->user_pixel_stride = s->pixel_stride;
      ch->user_line_stride = s->pixel_stride * w;
      ch->decode_to_ptr = s->base + (size_t)(cinfo.start_y - dw.min.y) * (size_t)ch->user_line_stride;
    }
    if (!dec_ready) {
      if ((r = exr_decoding_choose_default_routines(ctx, 0, &dec))) goto exr_error;
      dec_ready = 1;
    }
    if ((r = exr_decoding_run(ctx, 0, &dec))) goto exr_error;
  }
  goto done;
exr_error:
  rc = exr_fail(err, SL_ERR_FORMAT, path, "cannot read (truncated or corrupt?)", r);
done:
  if (dec_ready) exr_decoding_destroy(ctx, &dec);
  exr_finish(&ctx);
  if (rc) sl_image_free(img);
  return rc;
}

/* ---- PNG ---------------------------------------------------------------------------------- */

float sl_tonemap(float radiance, float exposure)
{
  const float x = radiance > 0.0f ? 1.0f - expf(-exposure * radiance) : 0.0f;
  /* IEC 61966-2-1 sRGB transfer function. */
  return x <= 0.0031308f ? 12.92f * x : 1.055f * powf(x, 1.0f / 2.4f) - 0.055f;
}

int sl_write_png_rgb8(const char *path, int width, int height, const unsigned char *rgb, sl_error *err)
{
  char tmp[4096];
  if (sl_temp_name(path, tmp, sizeof tmp, err)) return err->code;
  FILE *fp = fopen(tmp, "wb");
  if (!fp) return sl_fail(err, SL_ERR_IO, "%s: cannot create", path);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
  png_infop info = png ? png_create_info_struct(png) : NULL;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    fclose(fp);
    unlink(tmp);
    return sl_fail(err, SL_ERR_IO, "%s: cannot write PNG", path);
  }
  png_init_io(png, fp);
  png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) png_write_row(png, (png_const_bytep)(rgb + (size_t)y * width * 3));
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  if (fclose(fp) != 0) {
    unlink(tmp);
    return sl_fail(err, SL_ERR_IO, "%s: cannot write PNG", path);
  }
  return sl_temp_commit(tmp, path, err);
}

void sl_image_to_srgb8(const sl_image *img, float exposure, unsigned char *rgb)
{
  const size_t n = (size_t)img->width * img->height;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = sl_tonemap(img->rgba[4 * i + c], exposure);
      rgb[3 * i + c] = (unsigned char)lrintf(255.0f * (v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v));
    }
}

int sl_write_png(const char *path, const sl_image *img, float exposure, sl_error *err)
{
  unsigned char *rgb = malloc(3 * (size_t)img->width * img->height);
  if (!rgb) return sl_fail(err, SL_ERR_NOMEM, "%s: out of memory", path);
  sl_image_to_srgb8(img, exposure, rgb);
  const int rc = sl_write_png_rgb8(path, img->width, img->height, rgb, err);
  free(rgb);
  return rc;
}
