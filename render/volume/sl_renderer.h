/* The CPU volume renderer: half-angle slicing (Kniss et al. 2002) with a light buffer and an
 * eye buffer, compositing order chosen by the eye-sun angle (Riley et al. 2004, sec. 5).
 * Plan once, render many: sl_renderer_create(scene) prepares everything that does not depend
 * on the camera; sl_renderer_render(r, camera, image) draws one frame. */
#ifndef SL_RENDERER_H
#define SL_RENDERER_H

#include "sl_camera.h"
#include "sl_image.h"
#include "sl_optics.h"
#include "sl_sky.h"
#include "sl_status.h"
#include "sl_volume.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The GPU pass (app/gpu_volume_pass) carries eight particle fields, as the CPU: two RGBA textures. */
#define SL_GPU_MAX_FIELDS 8
#define SL_MAX_WAVELENGTHS SL_SKY_MAX_WAVELENGTHS /* carried per sample: the atmosphere's set */
#define SL_CHANNELS 3 /* output: linear sRGB; the paper's three wavelengths (650, 515, 440 nm) are
                          used as red, green and blue as they are, other sets go through CIE 1931 */

typedef enum sl_lighting {
  /* Single scattering with shadowing and a constant (isotropic) phase function: the comparison
   * model of Riley et al. 2004, Figure 13. */
  SL_LIGHTING_LOW_ALBEDO = 0,
  /* The multiple-scattering phase-function model (sec. 4.2): the light buffer carries intensity
   * and the expected scattering count n (eqs. 21-22), transported by eq. 24 taken continuously
   * in n; the eye gathers Ams_{n+1} + xi (eq. 26). */
  SL_LIGHTING_MULTIPLE = 1,
  /* The same with the paper's eq. 25 (worst-case order), kept for comparison. */
  SL_LIGHTING_MULTIPLE_EQ25 = 2
} sl_lighting;

typedef struct sl_scene {
  const sl_volume *volume;          /* not owned; must outlive the renderer */
  double sun_direction[3];          /* unit vector toward the sun, world ENU */
  /* The atmosphere (render/sky) for the paper's three wavelengths: sunlight attenuated down to
   * each sample's height (eq. 12), aerial perspective in front of the volume's midplane and sky
   * behind it (eqs. 14-15, sec. 5), the sun's disk (sec. 4.2.4). Not owned. NULL: no air, the
   * sun_irradiance below reaches the volume unattenuated and sky_radiance is a constant sky. */
  const sl_atmosphere *atmosphere;
  double sun_irradiance[SL_CHANNELS]; /* without an atmosphere: collimated irradiance at the volume */
  double sky_radiance[SL_CHANNELS]; /* without an atmosphere: constant background sky */
  /* Particle tables (render/optics) for the fields present and the atmosphere's wavelengths:
   * cross-sections, albedos, Ams_n and F_n. Not owned. Required by the multiple-scattering
   * lighting; NULL for the low-albedo model means Table 2's cross-sections and albedo 1. */
  const sl_optics_tables *optics;
  double xi;                        /* eq. 26's user back-scattering term, 1/sr (0: none) */
  int slices;                       /* slicing planes across the volume; 0: as many as resolve the grid */
  int light_resolution;             /* light-buffer texels along its longer side; 0 picks automatically */
  sl_lighting lighting;
  /* Front-to-back rays stop once their transparency falls below this (0: never). What is lost is
   * at most this fraction of what lies behind. */
  double termination_transparency;
  /* 1: light the volume once into a cached, view-independent light volume on the grid and draw
   * frames with a ray-marching eye pass (camera moves then cost only that pass); 0: half-angle
   * slicing per frame, the paper's method. */
  int light_volume;
  /* The light-volume eye march's samples per grid cell along a ray (1..8; 0: 1). More is slower
   * in proportion and nearer the march's limit (docs/ACCURACY.md, "The march's steps"). */
  int march_samples;
  /* The light-volume march's largest optical depth for a longer step (0: every step is 1/march_samples
   * of a cell). Where a step's 8^3 brick is thin enough that two or four steps together stay below
   * it in its densest sample, the march takes them as one, sampled at its middle: fewer samples
   * through thin anvils, rain and haze, where the light changes little within a step. A ray's
   * samples stay on the lattice of the short steps (docs/ACCURACY.md, "Thin steps"). */
  double march_thin_depth;
  /* The light-volume march's adaptive refinement (render/volume/pixel_refine.h; 0: a ray per
   * pixel). The rays of every 4th pixel are marched first; where a block's halfway rays agree with
   * the interpolation of its corner rays within this fraction (radiance and depth relatively, the
   * transparency as a difference) the pixels inside are interpolated, elsewhere the block splits,
   * down to every pixel (docs/ACCURACY.md, "Adaptive pixels"). */
  double march_refine_tolerance;
  /* 1: the sky dome lights the volume too (render/volume/sky_light.h: its diffuse light,
   * transmittance-weighted over the dome, gathered isotropically; docs/ACCURACY.md, "Skylight");
   * 0: the sun alone, the paper's model. */
  int skylight;
  /* 1: sunlight that the cloud has scattered out of the light buffer's forward cone lights the
   * volume too, carried by the skylight's lattice with the same closure (render/volume/sky_light.h;
   * docs/ACCURACY.md, "Diffuse sunlight"); 0: the light buffer alone, the paper's model. The
   * low-albedo model (single scattering) never takes it. */
  int diffuse_sunlight;
  /* Albedo of a flat Lambertian ground at sea level (the plane z = 0, or the sphere), lit by the
   * sun through the storm's shadow and by the clear sky, where the background's rays meet it; 0: a
   * black ground (only the air in front of it shines). */
  double ground_albedo;
  /* 1: run the passes' baseline x86-64 code even where the CPU offers AVX-512 (for comparing the
   * two builds of the same loops: speed, and that the images agree); 0: the widest the CPU has. */
  int baseline_isa;
  /* Called from one thread after each slice with the fraction done; may be NULL. */
  void (*progress)(void *user, double fraction);
  void *progress_user;
} sl_scene;


/* Which way the slices go for a camera: exposed for tests and reports. */
typedef struct sl_slicing {
  double half_vector[3];   /* slicing-plane normal, unit; slices are visited along +half_vector */
  int back_to_front;       /* 1 when the view vector was flipped: the eye composites back to front */
  double eye_sun_angle_deg;/* angle between the view direction and the direction to the sun */
} sl_slicing;

typedef struct sl_render_stats {
  int night;                         /* the sun is below the horizon: no sun, no sky from the model */
  double light_seconds, eye_seconds; /* summed over the frame's slices */
  double sky_seconds;                /* the skylight's lattice and the ground's shadow (0: kept from the last frame) */
  int slices, light_width, light_height;
  long eye_samples, light_samples;   /* samples that touched the volume's box */
  int wide_isa;                      /* 1: the passes ran their AVX-512 copy (sl_scene.baseline_isa) */
} sl_render_stats;

typedef struct sl_renderer sl_renderer;

sl_renderer *sl_renderer_create(const sl_scene *scene, sl_error *err);
void sl_renderer_destroy(sl_renderer *r);
/* img must be allocated at camera->width x camera->height. A renderer keeps what depends on the
 * sun but not on the camera from frame to frame (the cached light volume, the slicer's light
 * texels' rays): one thread at a time per renderer. */
int sl_renderer_render(sl_renderer *r, const sl_camera *camera, sl_image *img, sl_render_stats *stats,
                       sl_error *err);

/* Builds (or rebuilds) the cached light volume for the scene's sun; sl_renderer_render builds it
 * on first use when the scene asks for it. */
int sl_renderer_build_light_volume(sl_renderer *r, sl_error *err);

/* Builds what the sky and the sun light besides the volume's own light, for the current sun, if
 * not built yet: the skylight's lattice (sl_scene.skylight) and the ground's shadow map
 * (sl_scene.ground_albedo). sl_renderer_render does it on first use; sl_renderer_background
 * draws a lit ground only after it, and a GPU pass needs it before it draws. *seconds (may be
 * NULL) gets what building took, 0 when it was already built. */
int sl_renderer_prepare_sky(sl_renderer *r, double *seconds, sl_error *err);

/* A prepared renderer under another sun (unit vector toward it, world ENU): what depends on the
 * sun (the cached light volume) is dropped and rebuilt on next use; the extinction grids and the
 * tables are kept. What a viewer's sun change costs. */
int sl_renderer_set_sun(sl_renderer *r, const double sun_direction[3], sl_error *err);
/* Eq. 26's xi for the next frames; only the eye gather reads it (the light volume stays). */
void sl_renderer_set_xi(sl_renderer *r, double xi);
/* The light-volume march's samples per grid cell for the next frames (1..8; 0: 2); the light
 * volume stays. Returns SL_ERR_ARG outside the range. */
int sl_renderer_set_march_samples(sl_renderer *r, int samples, sl_error *err);

/* The background behind and around the volume for this camera, opaque: the whole ray's sky plus
 * the sun's disk (or the constant sky without an atmosphere). Its depth is the view-axis distance
 * to where the ray meets the atmosphere's ground (plane or sphere), +inf where it meets none. The volume layer
 * already carries the aerial perspective in front of the volume, so that
 * frame = volume + transparency * background (sl_image_over). */
int sl_renderer_background(const sl_renderer *r, const sl_camera *camera, sl_image *img, sl_error *err);

/* Per pixel (rows from the top), the sun's transparency from where its view ray reaches optical
 * depth 1 in the volume (its visible surface) toward the sun, by quadrature of the extinction; NaN
 * where the ray never reaches depth 1. Classes pixels for validation (below 1e-2: a face in the
 * cloud's own shadow, lit by the sky). out has width * height values. */
int sl_renderer_surface_sunlight(const sl_renderer *r, const sl_camera *camera, float *out, sl_error *err);

/* The box around the samples with non-zero extinction (the whole box when all are empty), with a
 * cell of margin; found as the renderer was built. */
void sl_renderer_content_bounds(const sl_renderer *r, double lo[3], double hi[3]);
/* The camera, its rays and the direction from compass angles: sl_camera.h (render/core). */

/* The earth as an opaque surface: lowers each pixel's distance (rows from the top, along the unit
 * ray, as sl_camera.opaque_distance) to where its ray meets the atmosphere's ground
 * (sl_sky_ground_distance: the plane z = 0 or the sphere), so eye rays stop there and what lies
 * beyond the horizon is hidden. distance has width * height values. */
void sl_camera_ground_distance(const sl_camera *cam, const sl_atmosphere *atm, float *distance);

/* Kniss et al.'s half-angle choice: h = normalize(v + p) when the view vector v and the light's
 * propagation direction p lie in the same hemisphere, else normalize(-v + p) with the eye
 * compositing back to front. Never degenerate: |±v + p| >= sqrt(2). */
void sl_choose_slicing(const double view_dir[3], const double sun_dir[3], sl_slicing *out);

/* The number of slices whose spacing gives the eye's central ray (view_dir) and the sunlight
 * (light_dir, the propagation direction) one sample per grid cell along every axis, for a box
 * `depth` metres deep along h: the data's own resolution. At least 256 (the paper's count,
 * which keeps slicing bands on optically thick surfaces fine) and at most 4096. */
int sl_slices_resolving_grid(const sl_volume *v, const double h[3], const double view_dir[3],
                             const double light_dir[3], double depth);

/* Total extinction coefficient (m^-1) of the hydrometeor fields at every grid sample with Table 2's
 * cross-sections, Riley et al. 2004, eqs. 2-3: beta_ex = sum_i eta_i sigma_ex,i (the renderer
 * itself uses the optics tables' cross-sections when it has them). */
int sl_total_extinction(const sl_volume *v, float *beta_out, sl_error *err);

#ifdef __cplusplus
}
#endif
#endif
