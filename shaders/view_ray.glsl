// Stormlight: a pixel's view ray and its span through the content box, shared by the eye pass and
// the resolve (the CPU's sl_camera_pixel_ray and sl_ray_box), in coordinates relative to the lattice's
// sample (0,0,0).
uniform vec3 slEye;            // camera position relative to the lattice's sample (0,0,0)
uniform vec3 slFwd, slRight, slUp;
uniform float slTanHalf, slAspect;
uniform vec2 slSize;
uniform vec3 slContentLo, slContentHi;

// The pinhole camera: pixel centres on an image plane at distance 1 along slFwd; py counts rows
// from the top.
vec3 slPixelRay(float px, float py)
{
  float sx = (2.0 * (px + 0.5) / slSize.x - 1.0) * slTanHalf * slAspect;
  float sy = (1.0 - 2.0 * (py + 0.5) / slSize.y) * slTanHalf;
  return normalize(slFwd + sx * slRight + sy * slUp);
}

// Slab intersection with the content box: [t0, t1] along d, false when the ray's line misses it.
bool slContentSpan(vec3 d, out float t0, out float t1)
{
  t0 = -3.0e38;
  t1 = 3.0e38;
  bool hit = true;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (slEye[a] < slContentLo[a] || slEye[a] > slContentHi[a]) hit = false;
      continue;
    }
    float ta = (slContentLo[a] - slEye[a]) / d[a], tb = (slContentHi[a] - slEye[a]) / d[a];
    t0 = max(t0, min(ta, tb));
    t1 = min(t1, max(ta, tb));
  }
  return hit;
}
