// Shared by the benchmarks: the storm resampled onto an n^3 grid.
#pragma once

#include <vtkColorTransferFunction.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPiecewiseFunction.h>
#include <vtkPointData.h>
#include <vtkVolumeProperty.h>

#include <algorithm>
#include <vector>

#include "sl_renderer.h"
#include "sl_volume.h"

// Trilinear resampling of every field onto n^3 samples spanning the same box.
inline bool resample(const sl_volume &in, int n, sl_volume *out)
{
  double lo[3], hi[3];
  sl_volume_bounds(&in, lo, hi);
  double origin[3], spacing[3];
  for (int a = 0; a < 3; ++a) {
    spacing[a] = (hi[a] - lo[a]) / n;
    origin[a] = lo[a] + 0.5 * spacing[a];
  }
  sl_error err{};
  if (sl_volume_init(out, n, n, n, origin, spacing, &err)) return false;
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p) {
    if (!in.eta[p]) continue;
    if (sl_volume_add_field(out, (sl_particle)p, &err)) return false;
    sl_grid_view g;
    sl_grid_view_init(&g, in.eta[p], &in);
#pragma omp parallel for schedule(static)
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const double x[3] = {origin[0] + i * spacing[0], origin[1] + j * spacing[1], origin[2] + k * spacing[2]};
          out->eta[p][sl_volume_index(out, i, j, k)] = (float)sl_grid_sample(&g, x);
        }
  }
  return true;
}

// VTK's peers render the same grid: total extinction as scalars, white, opacity rising to 0.5 at
// 1 % of the largest extinction, shading on, trilinear.
inline void peer_volume(const sl_volume *vol, vtkImageData *image, vtkVolumeProperty *prop)
{
  sl_error err{};
  std::vector<float> beta(sl_volume_count(vol));
  sl_total_extinction(vol, beta.data(), &err);
  const float beta_max = *std::max_element(beta.begin(), beta.end());
  image->SetDimensions(vol->nx, vol->ny, vol->nz);
  image->SetOrigin(vol->origin[0], vol->origin[1], vol->origin[2]);
  image->SetSpacing(vol->spacing[0], vol->spacing[1], vol->spacing[2]);
  vtkNew<vtkFloatArray> scalars;
  scalars->SetNumberOfTuples((vtkIdType)beta.size());
  for (size_t i = 0; i < beta.size(); ++i) scalars->SetValue((vtkIdType)i, beta[i]);
  image->GetPointData()->SetScalars(scalars);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.0);
  opacity->AddPoint(0.01 * beta_max, 0.5);
  opacity->AddPoint(beta_max, 1.0);
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 1, 1, 1);
  color->AddRGBPoint(beta_max, 1, 1, 1);
  prop->SetScalarOpacity(opacity);
  prop->SetColor(color);
  prop->ShadeOn();
  prop->SetInterpolationTypeToLinear();
}
