// The bounds of the three point-set volume mappers (their base
// vtkRayMapperParticleVolumeMapper), against a brute force written here: the box of the
// finite points grown on every side by the largest support a particle has,
//  - RBF: Sigma * ScaleFactor * r_max (the Gaussians are truncated at Sigma radii);
//  - SPH volume: the kernel's support per smoothing length (2 for the cubic spline and
//    Wendland C2, 1 for poly6, or SupportFactor) * ScaleFactor * h_max;
//  - SPH fluid: ScaleFactor * r_max (the spheres' union);
// with the constant radius when no ScaleArray is set, a NaN point and a NaN radius left out,
// and the same public API (the base's methods) on all three.
#include "vtkRBFVolumeMapper.h"
#include "vtkSPHFluidMapper.h"
#include "vtkSPHVolumeMapper.h"

#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace
{
bool ok = true;
void check(bool condition, const std::string& what)
{
  std::printf("%s %s\n", condition ? "ok  " : "FAIL", what.c_str());
  ok = ok && condition;
}

// Five points, one with a NaN coordinate, radii 0.5, 1.5, 0.25, 1 and a NaN one (skipped).
vtkSmartPointer<vtkPolyData> Particles()
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double xyz[5][3] = { { 0, 0, 0 }, { 2, -1, 3 }, { -1, 4, 1 }, { nan, 0, 0 },
    { 1, 1, -2 } };
  const double r[5] = { 0.5, 1.5, 0.25, 1.0, nan };
  vtkNew<vtkPoints> points;
  vtkNew<vtkDoubleArray> radii;
  radii->SetName("r");
  for (int i = 0; i < 5; ++i)
  {
    points->InsertNextPoint(xyz[i]);
    radii->InsertNextValue(r[i]);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(points);
  pd->GetPointData()->AddArray(radii);
  return pd;
}

// The brute force: the finite points' box grown by `support` (largest radius of the
// finite radii, 1.5 here, or the constant, times the method's factor).
void ExpectedBounds(double support, double b[6])
{
  const double finite[4][3] = { { 0, 0, 0 }, { 2, -1, 3 }, { -1, 4, 1 }, { 1, 1, -2 } };
  for (int a = 0; a < 3; ++a)
  {
    b[2 * a] = b[2 * a + 1] = finite[0][a];
    for (const auto& p : finite)
    {
      b[2 * a] = std::min(b[2 * a], p[a]);
      b[2 * a + 1] = std::max(b[2 * a + 1], p[a]);
    }
    b[2 * a] -= support;
    b[2 * a + 1] += support;
  }
}

void CheckBounds(vtkRayMapperParticleVolumeMapper* m, double support, const std::string& what)
{
  double expected[6];
  ExpectedBounds(support, expected);
  const double* b = m->GetBounds();
  bool same = true;
  for (int i = 0; i < 6; ++i)
  {
    same = same && std::abs(b[i] - expected[i]) <= 1e-12 * (1 + std::abs(expected[i]));
  }
  char text[256];
  std::snprintf(text, sizeof text, " (x %g..%g, expected %g..%g)", b[0], b[1], expected[0],
    expected[1]);
  check(same, what + text);
}

// The base's API reaches each mapper (C++; the Python wrapping inherits the same).
void CheckSharedApi(vtkRayMapperParticleVolumeMapper* m, const std::string& name)
{
  m->SetScaleArray("r");
  m->SetScaleFactor(2.0);
  m->SetNumberOfThreads(3);
  check(m->IsA("vtkAbstractVolumeMapper") && m->GetScaleArray() == std::string("r") &&
      m->GetScaleFactor() == 2.0 && m->GetNumberOfThreads() == 3 && m->GetStatistics(),
    name + ": ScaleArray, ScaleFactor, NumberOfThreads, GetStatistics from the base");
}
}

int TestParticleVolumeBounds(int, char*[])
{
  const auto input = Particles();
  vtkNew<vtkRBFVolumeMapper> rbf;
  vtkNew<vtkSPHVolumeMapper> sph;
  vtkNew<vtkSPHFluidMapper> fluid;
  for (vtkRayMapperParticleVolumeMapper* m :
    { static_cast<vtkRayMapperParticleVolumeMapper*>(rbf), static_cast<vtkRayMapperParticleVolumeMapper*>(sph),
      static_cast<vtkRayMapperParticleVolumeMapper*>(fluid) })
  {
    m->SetInputData(input);
    CheckSharedApi(m, m->GetClassName());
  }
  // The array r with factor 2 first (CheckSharedApi set them), then the constant sizes.
  rbf->SetSigma(3.0);
  CheckBounds(rbf, 3.0 * 2.0 * 1.5, "RBF: Sigma * ScaleFactor * r_max");
  sph->SetKernel(VTK_SPH_KERNEL_CUBIC_SPLINE);
  CheckBounds(sph, 2.0 * 2.0 * 1.5, "SPH volume: cubic spline 2 h_max * ScaleFactor");
  sph->SetKernel(VTK_SPH_KERNEL_POLY6);
  CheckBounds(sph, 1.0 * 2.0 * 1.5, "SPH volume: poly6 h_max * ScaleFactor");
  sph->SetSupportFactor(2.5);
  CheckBounds(sph, 2.5 * 2.0 * 1.5, "SPH volume: SupportFactor * h_max * ScaleFactor");
  CheckBounds(fluid, 2.0 * 1.5, "SPH fluid: ScaleFactor * r_max");

  rbf->SetScaleArray(nullptr);
  rbf->SetRadius(0.75);
  CheckBounds(rbf, 3.0 * 2.0 * 0.75, "RBF without ScaleArray: Sigma * ScaleFactor * Radius");
  sph->SetScaleArray(nullptr);
  sph->SetSmoothingLength(0.75);
  CheckBounds(sph, 2.5 * 2.0 * 0.75, "SPH volume without ScaleArray: SupportFactor * h");
  fluid->SetScaleArray(nullptr);
  fluid->SetRadius(0.75);
  CheckBounds(fluid, 2.0 * 0.75, "SPH fluid without ScaleArray: ScaleFactor * Radius");
  return ok ? 0 : 1;
}
