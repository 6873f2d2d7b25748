/* The light volume's sweep over the grid (light_volume_sweep.c on the CPU,
 * shaders/volume_light_sweep.glsl on the GPU): its planes lie across the sunlight's dominant grid
 * axis and are visited in the light's order; a sample takes the light state where its sun ray
 * crossed the previous plane. Worked out once here from the grid and the sun, read by both. */
#ifndef SL_SWEEP_GEOMETRY_H
#define SL_SWEEP_GEOMETRY_H

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sl_sweep_geometry {
  int axis, a1, a2;  /* the dominant axis of the sunlight's propagation; the planes' axes (rows along a1) */
  int first, step;   /* the first plane's index along axis, and +1 or -1 to the next */
  double path;       /* along the sunlight from one plane to the next, m */
  double shift[2];   /* where a sample's sun ray crossed the previous plane, in samples along a1, a2 */
  double first_path; /* fresh sunlight's path to the first plane's samples: from the box's face, half
                        a plane spacing before them */
} sl_sweep_geometry;

/* The sweep of a grid of n[3] samples, spacing[3] m apart, under the sun in direction sun (unit,
 * toward the sun). */
void sl_sweep_geometry_init(const int n[3], const double spacing[3], const double sun[3], sl_sweep_geometry *g);

#ifdef __cplusplus
}
#endif
#endif
