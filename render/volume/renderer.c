/* The renderer: its creation from a scene (the per-field extinction grids of Riley et al. 2004,
 * eqs. 2-3, the lighting model's tables, the empty-space bricks), its settings, and the entry
 * point that draws a frame with the half-angle slicer (slicer.c) or the cached light volume
 * (light_volume.c). */
#include "sl_renderer.h"

#include "lighting.h"
#include "renderer_internal.h"
#include "sl_cie.h"

#include <limits.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

int sl_total_extinction(const sl_volume *v, float *beta_out, sl_error *err)
{
  const size_t n = sl_volume_count(v);
  memset(beta_out, 0, n * sizeof(float));
  for (int k = 0; k < SL_VOLUME_SLOTS; ++k) {
    if (!v->eta[k]) continue;
    const sl_particle p = sl_volume_field_type(v, k);
    const double sigma = sl_particle_properties(p)->sigma_ext_m2;
    for (size_t i = 0; i < n; ++i) {
      const float eta = v->eta[k][i];
      if (!(eta >= 0.0f) || !isfinite(eta))
        return sl_fail(err, SL_ERR_DATA, "%s concentration is negative or not finite at sample %zu",
                       sl_particle_name(p), i);
      beta_out[i] += (float)(eta * sigma); /* Riley et al. 2004, eqs. 2-3 */
    }
  }
  return SL_OK;
}

sl_renderer *sl_renderer_create(const sl_scene *scene, sl_error *err)
{
  if (!scene || !scene->volume) {
    sl_fail(err, SL_ERR_ARG, "renderer: no volume");
    return NULL;
  }
  double sun[3] = {scene->sun_direction[0], scene->sun_direction[1], scene->sun_direction[2]};
  if (sl_normalize3(sun)) {
    sl_fail(err, SL_ERR_ARG, "renderer: the sun direction is not a finite non-zero vector");
    return NULL;
  }
  if (scene->slices < 0 || scene->slices > 16384) {
    sl_fail(err, SL_ERR_ARG, "renderer: %d slices is out of range (1..16384)", scene->slices);
    return NULL;
  }
  if (scene->march_samples < 0 || scene->march_samples > 8) {
    sl_fail(err, SL_ERR_ARG, "renderer: %d march samples per grid cell is out of range (1..8)", scene->march_samples);
    return NULL;
  }
  if (!(scene->march_thin_depth >= 0.0 && scene->march_thin_depth <= 1.0)) {
    sl_fail(err, SL_ERR_ARG, "renderer: march thin-step optical depth %g is out of range (0..1)",
            scene->march_thin_depth);
    return NULL;
  }
  if (!(scene->march_refine_tolerance >= 0.0 && scene->march_refine_tolerance <= 1.0)) {
    sl_fail(err, SL_ERR_ARG, "renderer: march refinement tolerance %g is out of range (0..1)",
            scene->march_refine_tolerance);
    return NULL;
  }
  if (scene->light_resolution < 0 || scene->light_resolution > 8192) {
    sl_fail(err, SL_ERR_ARG, "renderer: light-buffer resolution %d is out of range (1..8192)",
            scene->light_resolution);
    return NULL;
  }
  sl_renderer *r = calloc(1, sizeof *r);
  if (!r) {
    sl_fail(err, SL_ERR_NOMEM, "renderer: out of memory");
    return NULL;
  }
  r->scene = *scene;
  memcpy(r->scene.sun_direction, sun, sizeof sun);
  r->shape = *scene->volume;
  memset(r->shape.eta, 0, sizeof r->shape.eta);
  sl_grid_view_init(&r->lattice, NULL, &r->shape);
  sl_volume_bounds(&r->shape, r->lo, r->hi);
  if (sl_light_model_init(&r->model, scene, err)) {
    sl_renderer_destroy(r);
    return NULL;
  }
  r->has_subsets = r->model.mode == SL_LIGHTING_MULTIPLE && r->model.nf > 1;
  if (r->has_subsets)
    for (unsigned mask = 1; mask < 1u << r->model.nf; ++mask)
      sl_light_model_subset(&r->model, mask, &r->field_subsets[mask]);
  if (!scene->atmosphere && r->model.nwl != SL_CHANNELS) {
    sl_fail(err, SL_ERR_ARG, "renderer: without an atmosphere the renderer works in its three channels");
    sl_renderer_destroy(r);
    return NULL;
  }
  /* Three wavelengths are the paper's red, green and blue channels as they are; any other set is
   * spectral radiance, converted to linear sRGB through the CIE 1931 observer. */
  r->spectral = r->model.nwl != SL_CHANNELS;
  memset(r->to_rgb, 0, sizeof r->to_rgb);
  if (r->spectral) {
    if (sl_cie_srgb_weights(scene->atmosphere->wavelength_nm, r->model.nwl, 1, r->to_rgb, err)) {
      sl_renderer_destroy(r);
      return NULL;
    }
  } else {
    for (int c = 0; c < SL_CHANNELS; ++c) r->to_rgb[c * SL_CHANNELS + c] = 1.0;
  }
  /* Extinction per field from the tables' cross-sections (eq. 2), interleaved so one trilinear
   * look-up serves every field; their total (eq. 3) is summed where it is read
   * (sl__total_extinction). */
  const size_t count = sl_volume_count(scene->volume);
  const int nf = r->model.nf;
  const size_t field_bytes = ((nf > 0 ? nf : 1) * count + SL__FIELD_LANES) * sizeof(float); /* sl__field_fetch's last load */
  r->fields = sl__huge_calloc(field_bytes);
  if (!r->fields) {
    sl_fail(err, SL_ERR_NOMEM, "renderer: out of memory for the extinction grids");
    sl_renderer_destroy(r);
    return NULL;
  }
  if (nf <= 1) r->lattice.data = r->fields;
  /* The grid reads as zero: the loop writes only the samples that hold medium, so the clear air
   * of a storm, most of its grid, takes no memory in it (sl__huge_calloc). It reads only the
   * volume's content box, rows of it in parallel: at 1000 x 1000 x 160 samples the whole grid
   * took 9 s of one core. The first bad sample (the least index) is the one reported. */
  for (int j = 0; j < nf; ++j) sl__advise_huge_reads(scene->volume->eta[r->model.slot[j]], count * sizeof(float));
  int box_lo[3], box_hi[3];
  const int box_any = sl_volume_content_samples(scene->volume, box_lo, box_hi);
  const long rows = box_any ? sl_volume_box_rows(box_lo, box_hi) : 0;
  size_t bad = count;
  int bad_field = 0;
  double beta_max = 0.0;
  int any = 0;
  /* The samples that hold medium: their box gives the content bounds (sl_renderer_content_bounds). */
  int mn0 = INT_MAX, mn1 = INT_MAX, mn2 = INT_MAX, mx0 = -1, mx1 = -1, mx2 = -1;
  const int box_ny = box_hi[1] - box_lo[1] + 1;
#pragma omp parallel for schedule(static) reduction(max : beta_max, mx0, mx1, mx2) reduction(| : any) \
    reduction(min : mn0, mn1, mn2)
  for (long row = 0; row < rows; ++row) {
    const size_t first = sl_volume_box_row(scene->volume, box_lo, box_hi, row);
    const int row_j = box_lo[1] + (int)(row % box_ny), row_k = box_lo[2] + (int)(row / box_ny);
    for (size_t i = first; i <= first + (size_t)(box_hi[0] - box_lo[0]); ++i) {
      double total = 0.0;
      for (int j = 0; j < nf; ++j) {
        const float eta = scene->volume->eta[r->model.slot[j]][i];
        if (!(eta >= 0.0f) || !isfinite(eta)) {
#pragma omp critical(sl_renderer_bad_sample)
          if (i < bad) bad = i, bad_field = j;
        }
        const double b = eta * r->model.sigma_ext[j];
        if (b != 0.0) r->fields[i * nf + j] = (float)b;
        total += b;
      }
      if (total > beta_max) beta_max = total;
      any |= total > 0.0;
      if ((float)total > 0.0f) {
        const int x = box_lo[0] + (int)(i - first);
        if (x < mn0) mn0 = x;
        if (x > mx0) mx0 = x;
        if (row_j < mn1) mn1 = row_j;
        if (row_j > mx1) mx1 = row_j;
        if (row_k < mn2) mn2 = row_k;
        if (row_k > mx2) mx2 = row_k;
      }
    }
  }
  for (int j = 0; j < nf; ++j) sl__advise_reads_done(scene->volume->eta[r->model.slot[j]], count * sizeof(float));
  if (bad < count) {
    sl_fail(err, SL_ERR_DATA, "%s concentration is negative or not finite at sample %zu",
            sl_particle_name(r->model.field[bad_field]), bad);
    sl_renderer_destroy(r);
    return NULL;
  }
  r->beta_max = beta_max, r->any_extinction = any;
  if (sl__bricks_build(r, err)) {
    sl_renderer_destroy(r);
    return NULL;
  }
  const int medium_lo[3] = {mn0, mn1, mn2}, medium_hi[3] = {mx0, mx1, mx2};
  sl__content_bounds(r, medium_lo, medium_hi, r->clo, r->chi);
  for (int a = 0; a < 3; ++a) r->content_center[a] = 0.5 * (r->clo[a] + r->chi[a]);
  return r;
}

void sl_renderer_destroy(sl_renderer *r)
{
  if (!r) return;
  sl_light_model_free(&r->model);
  free(r->fields);
  free(r->light_volume);
  sl__sky_light_free(&r->sky);
  sl__ground_free(&r->ground);
  free(r->empty_radius);
  free(r->brick_beta_max);
  free(r->clear_blocks);
  free(r->texel_spans.u_in), free(r->texel_spans.u_out), free(r->texel_spans.first), free(r->texel_spans.last);
  free(r->texel_spans.u_entry);
  free(r);
}

int sl_renderer_prepare_sky(sl_renderer *r, double *seconds, sl_error *err)
{
  if (seconds) *seconds = 0.0;
  if (r->sky_built) return SL_OK;
  const double t0 = omp_get_wtime();
  if (sl__diffuse_lattice(&r->scene) && r->any_extinction && sl__sky_light_build(r, err)) return err->code;
  if (sl__ground_build(r, err)) return err->code;
  r->sky_built = 1;
  if (seconds) *seconds = omp_get_wtime() - t0;
  return SL_OK;
}

int sl_renderer_set_sun(sl_renderer *r, const double sun_direction[3], sl_error *err)
{
  double sun[3] = {sun_direction[0], sun_direction[1], sun_direction[2]};
  if (sl_normalize3(sun)) return sl_fail(err, SL_ERR_ARG, "renderer: the sun direction is not a finite non-zero vector");
  memcpy(r->scene.sun_direction, sun, sizeof sun);
  /* The cached light volume was lit by the old sun; the next frame that needs it rebuilds it. */
  free(r->light_volume);
  r->light_volume = NULL;
  sl__sky_light_free(&r->sky);
  sl__ground_free(&r->ground);
  r->sky_built = 0;
  return SL_OK;
}

int sl_renderer_set_march_samples(sl_renderer *r, int samples, sl_error *err)
{
  if (samples < 0 || samples > 8)
    return sl_fail(err, SL_ERR_ARG, "renderer: %d march samples per grid cell is out of range (1..8)", samples);
  r->scene.march_samples = samples;
  return SL_OK;
}

void sl_renderer_set_xi(sl_renderer *r, double xi)
{
  r->scene.xi = xi;
  r->model.xi = xi;
  for (int mask = 0; mask < 1 << SL_MAX_FIELDS; ++mask) r->field_subsets[mask].xi = xi;
}

int sl_renderer_render(sl_renderer *r, const sl_camera *cam, sl_image *img, sl_render_stats *stats, sl_error *err)
{
  if (!cam || cam->width != img->width || cam->height != img->height)
    return sl_fail(err, SL_ERR_ARG, "render: the image is not the camera's size");
  if (!(cam->fov_deg > 0.0 && cam->fov_deg < 170.0))
    return sl_fail(err, SL_ERR_ARG, "render: field of view %g degrees is out of range (0, 170)", cam->fov_deg);
  double fwd[3], right[3], up[3];
  if (sl_camera_basis(cam, fwd, right, up))
    return sl_fail(err, SL_ERR_ARG, "render: camera position equals the target, or up is parallel to the view");
  /* The skylight's lattice depends on the sun, not on the camera: built by the first frame under a sun. */
  double sky_seconds = 0.0;
  if (sl_renderer_prepare_sky(r, &sky_seconds, err)) return err->code;
  const int rc = r->scene.light_volume && r->any_extinction ? sl__render_with_light_volume(r, cam, img, stats, err)
                                                            : sl__render_slicer(r, cam, fwd, right, up, img, stats, err);
  if (!rc && stats) stats->sky_seconds = sky_seconds;
  return rc;
}
