/* Empty-space skipping changes nothing. First its two parts against brute force: each empty
 * brick's distance to the nearest occupied one (the chessboard metric, by its definition over
 * every pair of bricks), and the walk that finds where a ray first and last meets an occupied
 * brick, jumping whole cubes of empty bricks, against a march of 20000 points per ray.
 * Then images: a sparse volume (isolated voxels and small blobs, some on
 * the 8^3 bricks' faces and in the grid's last cells, whose bricks are clamped) is rendered as it
 * is, where the slicer walks each ray through the brick lattice and the light-volume march jumps
 * empty bricks, and again with a background so faint (optical depth below 1e-8 across the box)
 * that it cannot show but marks every brick occupied, so nothing is skipped. The two images must
 * agree to float rounding; a skipped occupied brick would cost a whole voxel's light.
 * In the multiple-scattering model the slicer also leaves out, per batch of samples, the table
 * reads of fields the batch does not hold (the cloud blobs and the ice blobs lie apart); the faint
 * background puts both fields in every batch, so there the full model runs: a field given the
 * other's tables (cloud droplets' rainbow, ice's halo) would change the image far beyond rounding. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "coarse_optics.h"
#include "renderer_internal.h"
#include "sl_optics.h"
#include "sl_renderer.h"
#include "sl_testing.h"

enum { NX = 37, NY = 29, NZ = 21 };

static void fill(sl_volume *v, int background)
{
  for (int p = 0; p < 2; ++p) {
    float *eta = v->eta[p == 0 ? SL_CLOUD : SL_ICE];
    const size_t n = sl_volume_count(v);
    /* Table 2's cross-sections: 1e-3 cloud droplets or 1e-6 ice crystals per cubic metre give
     * an extinction near 1e-12 per metre, a few 1e-9 across the 4 km box. */
    for (size_t i = 0; i < n; ++i) eta[i] = background ? (p == 0 ? 1e-3f : 1e-6f) : 0.0f;
  }
  unsigned s = 12345u;
  float *cloud = v->eta[SL_CLOUD], *ice = v->eta[SL_ICE];
  /* The two opposite corners: the content box is the whole box in both renders. */
  cloud[sl_volume_index(v, 0, 0, 0)] = 2e7f;
  cloud[sl_volume_index(v, NX - 1, NY - 1, NZ - 1)] = 2e7f;
  /* Brick faces (7|8, 15|16, 23|24) and the last cells. */
  const int edges[][3] = {{7, 8, 7}, {8, 7, 8}, {15, 16, 15}, {16, 15, 16}, {NX - 1, 3, 5}, {NX - 2, NY - 1, 9},
                          {4, NY - 2, NZ - 1}, {23, 24, 20}, {24, 23, 0}, {31, 0, 12}};
  for (size_t e = 0; e < sizeof edges / sizeof edges[0]; ++e)
    cloud[sl_volume_index(v, edges[e][0], edges[e][1], edges[e][2])] = 3e7f;
  for (int b = 0; b < 12; ++b) {
    s = s * 1664525u + 1013904223u;
    const int i0 = (int)(s % (NX - 3)), j0 = (int)((s >> 8) % (NY - 3)), k0 = (int)((s >> 16) % (NZ - 3));
    for (int k = k0; k < k0 + 2; ++k)
      for (int j = j0; j < j0 + 3; ++j)
        for (int i = i0; i < i0 + 2; ++i) (b % 2 ? ice : cloud)[sl_volume_index(v, i, j, k)] = b % 2 ? 4e4f : 1e7f;
  }
}

/* Relative RMSE of b against a over the RGB channels, and the largest difference relative to
 * a's brightest channel. */
static void difference(const sl_image *a, const sl_image *b, double *rel_rmse, double *rel_max)
{
  const size_t n = (size_t)a->width * a->height;
  double num = 0.0, den = 0.0, dmax = 0.0, vmax = 0.0;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double x = a->rgba[4 * i + c], y = b->rgba[4 * i + c];
      num += (x - y) * (x - y), den += x * x;
      dmax = fmax(dmax, fabs(x - y)), vmax = fmax(vmax, fabs(x));
    }
  *rel_rmse = den > 0.0 ? sqrt(num / den) : INFINITY;
  *rel_max = vmax > 0.0 ? dmax / vmax : INFINITY;
}

static unsigned long long rng = 2463534242ULL;
static double uniform(void)
{
  rng = rng * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(rng >> 11) / 9007199254740992.0;
}

static void test_empty_radius(void)
{
  /* Shapes with a single brick along some axes, and one longer than the 255 the radius is
   * capped at; none, one and a few per cent of the bricks occupied. */
  const int shapes[][3] = {{7, 5, 4}, {1, 9, 1}, {12, 1, 3}, {6, 6, 6}, {3, 4, 1}, {300, 1, 2}};
  const double fill[] = {0.0, -1.0, 0.05};
  int worst = 0;
  for (size_t si = 0; si < sizeof shapes / sizeof shapes[0]; ++si)
    for (size_t fi = 0; fi < sizeof fill / sizeof fill[0]; ++fi) {
      const int *n = shapes[si];
      const size_t count = (size_t)n[0] * n[1] * n[2];
      unsigned char *radius = malloc(count), *occupied = malloc(count);
      for (size_t i = 0; i < count; ++i) occupied[i] = fill[fi] > 0.0 && uniform() < fill[fi];
      if (fill[fi] < 0.0) occupied[0] = 1; /* one, in a corner: distances run the whole lattice */
      for (size_t i = 0; i < count; ++i) radius[i] = occupied[i] ? 0 : 1;
      sl__brick_empty_radius(n, radius);
      int wrong = 0;
      for (size_t i = 0; i < count; ++i) {
        const int x = (int)(i % n[0]), y = (int)(i / n[0] % n[1]), z = (int)(i / ((size_t)n[0] * n[1]));
        int want = 255;
        for (size_t j = 0; j < count; ++j) {
          if (!occupied[j]) continue;
          const int dx = abs(x - (int)(j % n[0])), dy = abs(y - (int)(j / n[0] % n[1])),
                    dz = abs(z - (int)(j / ((size_t)n[0] * n[1])));
          const int dist = dx > dy ? (dx > dz ? dx : dz) : (dy > dz ? dy : dz);
          if (dist < want) want = dist;
        }
        wrong += radius[i] != want;
        if (abs(radius[i] - want) > worst) worst = abs(radius[i] - want);
      }
      char what[160];
      snprintf(what, sizeof what, "empty radius of %dx%dx%d bricks, fill %g: %d of %zu bricks wrong", n[0], n[1], n[2],
               fill[fi], wrong, count);
      CHECK_MSG(wrong == 0, what);
      free(radius), free(occupied);
    }
  printf("empty radius against brute force: largest difference %d bricks\n", worst);
}

/* sl__occupied_span against a march of 20000 points per ray through a 150x110x70 lattice
 * (19x14x9 bricks) holding a few blobs: the span may not start after the march's first occupied
 * point nor end before its last (that would skip cloud), and not by more than one march step
 * before or after them; a ray whose span the march finds empty may graze a brick only. */
static void test_walk(void)
{
  enum { WX = 150, WY = 110, WZ = 70 };
  sl_error err = {0};
  sl_volume v;
  const double spacing[3] = {100.0, 120.0, 50.0}, origin[3] = {-7000.0, 3000.0, 0.0};
  if (!CHECK(sl_volume_init(&v, WX, WY, WZ, origin, spacing, &err) == SL_OK)) return;
  CHECK(sl_volume_add_field(&v, SL_CLOUD, &err) == SL_OK);
  float *cloud = v.eta[SL_CLOUD];
  for (size_t i = 0; i < sl_volume_count(&v); ++i) cloud[i] = 0.0f;
  double aim[9][3];
  for (int b = 0; b < 9; ++b) {
    const int i0 = (int)(uniform() * (WX - 4)), j0 = (int)(uniform() * (WY - 4)), k0 = (int)(uniform() * (WZ - 4));
    aim[b][0] = origin[0] + i0 * spacing[0], aim[b][1] = origin[1] + j0 * spacing[1], aim[b][2] = origin[2] + k0 * spacing[2];
    for (int k = k0; k < k0 + (b % 3) + 1; ++k)
      for (int j = j0; j < j0 + 2; ++j)
        for (int i = i0; i < i0 + 3; ++i) cloud[sl_volume_index(&v, i, j, k)] = 1e7f;
  }
  cloud[sl_volume_index(&v, WX - 1, 40, 30)] = 1e7f; /* in the last, clamped cells */
  cloud[sl_volume_index(&v, 70, WY - 1, WZ - 1)] = 1e7f;
  sl_scene sc = {.volume = &v, .slices = 64, .lighting = SL_LIGHTING_LOW_ALBEDO};
  sl_sun_direction(35.0, 240.0, sc.sun_direction);
  for (int c = 0; c < SL_CHANNELS; ++c) sc.sun_irradiance[c] = 1.0;
  sl_renderer *r = sl_renderer_create(&sc, &err);
  if (!CHECK_MSG(r != NULL, err.message)) return;
  double lo[3], hi[3];
  sl_volume_bounds(&v, lo, hi);
  int rays = 0, crossing = 0, late = 0, early = 0, missed = 0, grazing = 0, jumped = 0;
  for (int k = 0; k < 3000; ++k) {
    double o[3], d[3], t0, t1;
    /* From outside the box or inside it; random directions, some along an axis or a diagonal. */
    for (int a = 0; a < 3; ++a) o[a] = lo[a] + (hi[a] - lo[a]) * (k % 3 ? 1.6 * uniform() - 0.3 : uniform());
    const double z = 2.0 * uniform() - 1.0, phi = 2.0 * M_PI * uniform();
    d[0] = sqrt(1.0 - z * z) * cos(phi), d[1] = sqrt(1.0 - z * z) * sin(phi), d[2] = z;
    if (k % 2) {
      /* Toward a blob's voxel, give or take a cell. */
      const int b = (int)(uniform() * 9);
      for (int a = 0; a < 3; ++a) d[a] = aim[b][a] + spacing[a] * (2.0 * uniform() - 1.0) - o[a];
      sl_normalize3(d);
    }
    if (k % 10 == 1) d[0] = d[1] = 0.0, d[2] = k % 20 == 1 ? 1.0 : -1.0;
    if (k % 10 == 2) d[0] = d[2] = sqrt(0.5), d[1] = 0.0;
    if (k % 10 == 3) d[0] = d[1] = d[2] = -sqrt(1.0 / 3.0);
    if (!sl_ray_box(r->clo, r->chi, o, d, &t0, &t1)) continue;
    if (t0 < 0.0) t0 = 0.0;
    if (!(t1 > t0)) continue;
    ++rays;
    double first, last;
    sl__occupied_span(r, o, d, t0, t1, &first, &last);
    const int n = 20000;
    const double dt = (t1 - t0) / n, tol = 1e-9 * (fabs(t0) + fabs(t1));
    double m_first = INFINITY, m_last = -INFINITY;
    for (int i = 0; i < n; ++i) {
      const double t = t0 + (i + 0.5) * dt;
      const double x[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
      int cell[3];
      double f[3];
      sl__lattice_cell(&r->lattice, x, cell, f);
      if (!sl__brick_occupied(r, cell)) continue;
      if (t < m_first) m_first = t;
      m_last = t;
    }
    if (m_first <= m_last) {
      ++crossing;
      late += !(first <= m_first + tol) || !(last >= m_last - tol);
      early += !(first >= m_first - dt - tol) || !(last <= m_last + dt + tol);
      if (first > last) ++missed;
    } else if (first <= last) {
      grazing += !(last - first <= 2.0 * dt);
    }
    jumped += first > t0 + 8.0 * 50.0; /* walks that crossed empty bricks */
  }
  char what[300];
  snprintf(what, sizeof what,
           "occupied span against a march: %d rays (%d cross cloud, %d start in empty space): %d end too late, "
           "%d too early, %d missed, %d find cloud the march does not",
           rays, crossing, jumped, late, early, missed, grazing);
  printf("%s\n", what);
  CHECK_MSG(rays > 1500 && crossing > 500 && late == 0 && early == 0 && missed == 0 && grazing == 0, what);
  sl_renderer_destroy(r);
  sl_volume_free(&v);
}

int main(void)
{
  test_empty_radius();
  test_walk();
  sl_error err = {0};
  sl_volume sparse, faint;
  const double spacing[3] = {100.0, 120.0, 50.0};
  const double origin[3] = {-0.5 * (NX - 1) * spacing[0], -0.5 * (NY - 1) * spacing[1], 200.0};
  sl_volume *vols[2] = {&sparse, &faint};
  for (int w = 0; w < 2; ++w) {
    if (!CHECK(sl_volume_init(vols[w], NX, NY, NZ, origin, spacing, &err) == SL_OK)) return sl_test_finish("test_empty_space");
    CHECK(sl_volume_add_field(vols[w], SL_CLOUD, &err) == SL_OK);
    CHECK(sl_volume_add_field(vols[w], SL_ICE, &err) == SL_OK);
    fill(vols[w], w);
  }
  /* Coarse tables: the test compares two renders with the same tables. */
  sl_optics_tables *optics = coarse_optics((1u << SL_CLOUD) | (1u << SL_ICE), &err);
  if (!CHECK_MSG(optics != NULL, err.message)) return sl_test_finish("test_empty_space");
  /* Sun: oblique, and straight down (texel rays along one axis only). View: from several sides,
   * toward and away from the sun, and from inside the box. */
  const double suns[][2] = {{240.0, 35.0}, {0.0, 90.0}};
  const double views[][2] = {{200.0, 12.0}, {60.0, -20.0}, {240.0, 35.0}, {0.0, 89.0}};
  const char *mode_name[3] = {"slicer", "light volume", "slicer, multiple scattering"};
  for (int mode = 0; mode < 3; ++mode)
    for (size_t si = 0; si < 2; ++si)
      for (size_t vi = 0; vi < sizeof views / sizeof views[0] + 1; ++vi) {
        sl_image img[2];
        for (int w = 0; w < 2; ++w) {
          sl_scene sc = {.volume = vols[w], .slices = 64, .lighting = SL_LIGHTING_LOW_ALBEDO, .light_volume = mode == 1};
          if (mode == 2) sc.lighting = SL_LIGHTING_MULTIPLE, sc.optics = optics, sc.xi = 0.01, sc.diffuse_sunlight = 1;
          sl_sun_direction(suns[si][1], suns[si][0], sc.sun_direction);
          for (int c = 0; c < SL_CHANNELS; ++c) sc.sun_irradiance[c] = 1.0, sc.sky_radiance[c] = 0.0;
          sl_renderer *r = sl_renderer_create(&sc, &err);
          if (!CHECK(r != NULL)) return sl_test_finish("test_empty_space");
          double lo[3], hi[3];
          sl_volume_bounds(vols[w], lo, hi);
          sl_camera cam;
          if (vi < sizeof views / sizeof views[0]) {
            sl_camera_frame(lo, hi, views[vi][0], views[vi][1], 40.0, 64, 48, &cam);
          } else {
            sl_camera_frame(lo, hi, 130.0, 10.0, 70.0, 64, 48, &cam);
            for (int a = 0; a < 3; ++a) cam.position[a] = lo[a] + 0.3 * (hi[a] - lo[a]); /* inside */
          }
          sl_image_alloc(&img[w], cam.width, cam.height, &err);
          CHECK(sl_renderer_render(r, &cam, &img[w], NULL, &err) == SL_OK);
          sl_renderer_destroy(r);
        }
        double rel_rmse, rel_max;
        difference(&img[1], &img[0], &rel_rmse, &rel_max);
        char what[160];
        snprintf(what, sizeof what, "%s, sun %zu, view %zu: skipping leaves the image as it is (rmse %.2g, max %.2g)",
                 mode_name[mode], si, vi, rel_rmse, rel_max);
        CHECK_MSG(rel_rmse < 1e-5 && rel_max < 1e-5, what);
        double sum = 0.0;
        for (size_t i = 0; i < (size_t)img[0].width * img[0].height; ++i) sum += img[0].rgba[4 * i];
        snprintf(what, sizeof what, "%s, sun %zu, view %zu: the voxels are seen", mode_name[mode], si, vi);
        CHECK_MSG(sum > 0.0, what);
        sl_image_free(&img[0]);
        sl_image_free(&img[1]);
      }
  /* Changing xi on a live renderer (the viewer's slider) reaches the per-batch field subsets too:
   * a renderer made with another xi and set to 0.01 renders what one made with 0.01 does. */
  {
    sl_image img[2];
    for (int w = 0; w < 2; ++w) {
      sl_scene sc = {.volume = &sparse, .slices = 64, .lighting = SL_LIGHTING_MULTIPLE, .optics = optics,
                     .xi = w ? 0.2 : 0.01};
      sl_sun_direction(35.0, 240.0, sc.sun_direction);
      for (int c = 0; c < SL_CHANNELS; ++c) sc.sun_irradiance[c] = 1.0, sc.sky_radiance[c] = 0.0;
      sl_renderer *r = sl_renderer_create(&sc, &err);
      if (!CHECK(r != NULL)) return sl_test_finish("test_empty_space");
      if (w) sl_renderer_set_xi(r, 0.01);
      double lo[3], hi[3];
      sl_volume_bounds(&sparse, lo, hi);
      sl_camera cam;
      sl_camera_frame(lo, hi, 200.0, 12.0, 40.0, 64, 48, &cam);
      sl_image_alloc(&img[w], cam.width, cam.height, &err);
      CHECK(sl_renderer_render(r, &cam, &img[w], NULL, &err) == SL_OK);
      sl_renderer_destroy(r);
    }
    double rel_rmse, rel_max;
    difference(&img[0], &img[1], &rel_rmse, &rel_max);
    char what[160];
    snprintf(what, sizeof what, "xi set on a live renderer equals xi at creation (rmse %.2g, max %.2g)", rel_rmse,
             rel_max);
    CHECK_MSG(rel_rmse == 0.0 && rel_max == 0.0, what);
    sl_image_free(&img[0]);
    sl_image_free(&img[1]);
  }
  /* The slicer keeps its light texels' rays and occupied stretches from frame to frame while the
   * sun and the texel lattice stay (sl__texel_spans): a live renderer's frames (the same view
   * again, a new sun, the first sun again from another side and then as at first) equal a fresh
   * renderer's bitwise; a stale stretch under a new sun would skip these sparse voxels' bricks. */
  {
    const double frames[][4] = {{240.0, 35.0, 200.0, 12.0}, {240.0, 35.0, 200.0, 12.0}, {0.0, 90.0, 200.0, 12.0},
                                {240.0, 35.0, 60.0, -20.0}, {240.0, 35.0, 200.0, 12.0}};
    const int n_frames = (int)(sizeof frames / sizeof frames[0]);
    sl_scene sc = {.volume = &sparse, .slices = 64, .lighting = SL_LIGHTING_MULTIPLE, .optics = optics, .xi = 0.01};
    for (int c = 0; c < SL_CHANNELS; ++c) sc.sun_irradiance[c] = 1.0, sc.sky_radiance[c] = 0.0;
    sl_sun_direction(frames[0][1], frames[0][0], sc.sun_direction);
    sl_renderer *live = sl_renderer_create(&sc, &err);
    if (!CHECK(live != NULL)) return sl_test_finish("test_empty_space");
    double lo[3], hi[3];
    sl_volume_bounds(&sparse, lo, hi);
    sl_image img[2];
    sl_image_alloc(&img[0], 64, 48, &err);
    sl_image_alloc(&img[1], 64, 48, &err);
    for (int k = 0; k <= n_frames; ++k) {
      /* The last turn repeats the last frame with its kept stretches spoiled (none crosses a
       * brick), so that the frames above are known to have read them. */
      const int spoil = k == n_frames;
      const double *fr = frames[spoil ? n_frames - 1 : k];
      sl_sun_direction(fr[1], fr[0], sc.sun_direction);
      sl_camera cam;
      sl_camera_frame(lo, hi, fr[2], fr[3], 40.0, 64, 48, &cam);
      CHECK(sl_renderer_set_sun(live, sc.sun_direction, &err) == SL_OK);
      if (spoil) {
        CHECK_MSG(live->texel_spans.valid, "the slicer kept its texels' spans after a frame");
        for (size_t t = 0; t < live->texel_spans.capacity; ++t) live->texel_spans.last[t] = -INFINITY;
      }
      CHECK(sl_renderer_render(live, &cam, &img[0], NULL, &err) == SL_OK);
      sl_renderer *fresh = sl_renderer_create(&sc, &err);
      if (!CHECK(fresh != NULL)) return sl_test_finish("test_empty_space");
      CHECK(sl_renderer_render(fresh, &cam, &img[1], NULL, &err) == SL_OK);
      sl_renderer_destroy(fresh);
      double rel_rmse, rel_max;
      difference(&img[1], &img[0], &rel_rmse, &rel_max);
      char what[160];
      if (spoil) {
        snprintf(what, sizeof what, "spoiled kept spans change the frame, so frames read them (rmse %.2g)", rel_rmse);
        CHECK_MSG(rel_rmse > 1e-3, what);
      } else {
        snprintf(what, sizeof what, "live renderer's frame %d equals a fresh renderer's (rmse %.2g, max %.2g)", k,
                 rel_rmse, rel_max);
        CHECK_MSG(rel_rmse == 0.0 && rel_max == 0.0, what);
      }
    }
    sl_image_free(&img[0]);
    sl_image_free(&img[1]);
    sl_renderer_destroy(live);
  }
  sl_optics_free(optics);
  sl_volume_free(&sparse);
  sl_volume_free(&faint);
  return sl_test_finish("test_empty_space");
}
