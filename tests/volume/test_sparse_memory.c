/* Clear air costs no memory: a storm's grid is mostly clear air, and the renderer's extinction
 * grids (the interleaved fields and their total, sl__huge_calloc) take memory only where a sample
 * holds medium. A 512 x 512 x 128 grid of two fields (402 MB of the renderer's floats) with one
 * small cloud: creating the renderer must add far less to the resident set than those grids'
 * size, which writing every sample (zeros included) would add whole; with the volume's content box
 * known (as the loader sets it) it reads nothing outside it, and the frame is the same bit for
 * bit as with the box unknown. The bound leaves room for
 * the huge pages the cloud's levels take (2 MiB per level of the interleaved grid) and for the
 * reads of the loaded fields' clear air (the kernel's zero page, not resident). Linux only (the
 * resident set from /proc/self/statm). The bound is not checked under AddressSanitizer, whose own
 * allocator and shadow memory stand between calloc and the pages, nor on a kernel that gives reads
 * of never-written memory pages of their own (found by a probe, and said). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sl_renderer.h"
#include "sl_testing.h"

enum { NX = 512, NY = 512, NZ = 128, BLOB = 16 };

/* The resident set in bytes, or -1 where /proc is not there. */
static double resident_bytes(void)
{
  FILE *f = fopen("/proc/self/statm", "r");
  if (!f) return -1.0;
  long size = 0, resident = -1;
  if (fscanf(f, "%ld %ld", &size, &resident) != 2) resident = -1;
  fclose(f);
  return resident < 0 ? -1.0 : (double)resident * (double)sysconf(_SC_PAGESIZE);
}

/* 1 when reading never-written anonymous memory maps the kernel's shared zero page, as Linux does,
 * so that it takes no memory; 0 where each read page becomes resident (seen on Linux 6.18 in a
 * Firecracker VM), where reading a grid's clear air costs its size whatever the renderer does. */
static int kernel_maps_zero_page(void)
{
  const size_t bytes = (size_t)16 << 20;
  volatile unsigned char *p = calloc(1, bytes);
  if (!p) return 0;
  const double before = resident_bytes();
  unsigned sum = 0;
  for (size_t i = 0; i < bytes; i += 4096) sum += p[i];
  const double after = resident_bytes();
  free((void *)p);
  return sum == 0 && after - before < 0.25 * (double)bytes;
}

int main(void)
{
  sl_error err = {0};
  sl_volume v;
  const double spacing[3] = {250.0, 250.0, 100.0}, origin[3] = {0.0, 0.0, 50.0};
  if (!CHECK(sl_volume_init(&v, NX, NY, NZ, origin, spacing, &err) == SL_OK)) return sl_test_finish("test_sparse_memory");
  CHECK(sl_volume_add_field(&v, SL_CLOUD, &err) == SL_OK);
  CHECK(sl_volume_add_field(&v, SL_ICE, &err) == SL_OK);
  /* One cloud of BLOB^3 samples, ice in its top half. */
  for (int k = 40; k < 40 + BLOB; ++k)
    for (int j = 200; j < 200 + BLOB; ++j)
      for (int i = 300; i < 300 + BLOB; ++i) {
        v.eta[SL_CLOUD][sl_volume_index(&v, i, j, k)] = 1e8f;
        if (k >= 40 + BLOB / 2) v.eta[SL_ICE][sl_volume_index(&v, i, j, k)] = 1e5f;
      }
  sl_scene sc = {.volume = &v, .slices = 64, .lighting = SL_LIGHTING_LOW_ALBEDO};
  sl_sun_direction(35.0, 240.0, sc.sun_direction);
  for (int c = 0; c < SL_CHANNELS; ++c) sc.sun_irradiance[c] = 1.0;
  const int zero_page = kernel_maps_zero_page();
  const double grids = (double)sl_volume_count(&v) * (2 + 1) * sizeof(float);
  /* First with the volume's content box known, as the loader sets it (the cloud's samples), then
   * unknown (the whole grid), as a volume filled by hand has it. */
  sl_image img[2];
  for (int known = 1; known >= 0; --known) {
    v.content_known = known;
    for (int a = 0; a < 3; ++a) v.content_lo[a] = (int[3]){300, 200, 40}[a], v.content_hi[a] = v.content_lo[a] + BLOB - 1;
    const double before = resident_bytes();
    sl_renderer *r = sl_renderer_create(&sc, &err);
    const double after = resident_bytes();
    if (!CHECK_MSG(r != NULL, err.message)) return sl_test_finish("test_sparse_memory");
    printf("content box %s: renderer's grids %.0f MB; resident set grew by %.1f MB\n", known ? "known" : "unknown",
           grids / 1e6, (after - before) / 1e6);
#if defined(__SANITIZE_ADDRESS__)
    (void)zero_page;
    printf("AddressSanitizer: the bound is not checked\n");
#else
    /* With the box known the renderer reads nothing outside it, so the bound holds on any kernel. */
    if (!zero_page && !known)
      printf("this kernel gives reads of never-written memory pages of their own: the bound is not checked\n");
    else if (before >= 0.0 && after >= 0.0)
      CHECK_MSG(after - before < 0.25 * grids, known ? "the renderer's clear air took memory (box known)"
                                                     : "the renderer's clear air took memory");
#endif
    /* The grids read as zero in the clear air and hold the cloud where it is: the content box is
     * the cloud's samples and the cell around them that their trilinear footprint reaches. */
    double lo[3], hi[3];
    sl_renderer_content_bounds(r, lo, hi);
    const int first[3] = {300, 200, 40};
    for (int a = 0; a < 3; ++a) {
      CHECK_CLOSE(lo[a], origin[a] + (first[a] - 1) * spacing[a], 0.0, 1e-6 * spacing[a]);
      CHECK_CLOSE(hi[a], origin[a] + (first[a] + BLOB) * spacing[a], 0.0, 1e-6 * spacing[a]);
    }
    /* The same frame either way, bit for bit: the box only spares reading zeros. */
    sl_camera cam;
    sl_camera_frame(lo, hi, 200.0, 15.0, 40.0, 48, 32, &cam);
    sl_image_alloc(&img[known], cam.width, cam.height, &err);
    CHECK(sl_renderer_render(r, &cam, &img[known], NULL, &err) == SL_OK);
    sl_renderer_destroy(r);
  }
  const size_t values = (size_t)4 * img[0].width * img[0].height;
  double peak = 0.0;
  for (size_t i = 0; i < values; ++i) peak = img[1].rgba[i] > peak ? img[1].rgba[i] : peak;
  CHECK(peak > 0.0);
  CHECK_MSG(memcmp(img[0].rgba, img[1].rgba, values * sizeof(float)) == 0, "the content box changes the frame");
  sl_image_free(&img[0]);
  sl_image_free(&img[1]);
  sl_volume_free(&v);
  return sl_test_finish("test_sparse_memory");
}
