// The fluid's front surface against the analytic union of the particles' spheres
// (Testing/References: each pixel's ray against every sphere in closed form), on the PySPH
// dam break (9360 particles of radius 0.8 h = 0.0416 m): vtkSPHFluidMapper in a real render
// window, opaque (Translucency off, so it writes its front surface's depth), at its defaults
// otherwise (AngleResolution 14 degrees, no smoothing), with AngleResolution 7 and with
// AngleResolution 3; and the filter vtkSPHVoxelizer's EntryDepth at its defaults. Compared: the
// pixels where one shows fluid and the other not, and, where both do, the distance between
// the two surfaces along the pixel's ray, in radii.
//
// Measured on this machine (200 x 150; 12327 pixels show fluid, none of them only in one of
// the two): the largest / mean distance between the surfaces, in radii, is 0.073 / 0.028 at
// the defaults and for the filter, 0.037 / 0.014 at AngleResolution 7, 0.016 / 0.006 at
// AngleResolution 3: the voxelization's depth layers are about AngleResolution (radians)
// times the depth thick, and the surface is found within a layer. The bounds are 1.5 times
// the measured distances; at most 5 pixels may be covered by one surface only (grazing
// silhouettes).
//
// usage: TestSPHFluidMapperReference -D <Data dir>
#include "ReferenceFromVTK.h"
#include "ReferenceRenderers.h"
#include "RenderingTestHelpers.h"
#include "vtkSPHFluidMapper.h"
#include "vtkSPHVoxelizer.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkPolyDataReader.h"
#include "vtkTestUtilities.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>

namespace ref = raymappers::reference;

namespace
{
struct SurfaceDifference
{
  int onlyOne = 0;  // pixels covered by one surface and not the other
  int both = 0;     // pixels covered by both
  double worst = 0; // largest distance between them along the ray, in radii
  double mean = 0;  // mean distance
};

// `t[p]`: the distance from pixel p's near-plane point to the tested surface (< 0: none).
SurfaceDifference Compare(const ref::ReferenceCamera& cam,
  const ref::ReferenceImage& expected,
  const std::vector<double>& t,
  double radius)
{
  SurfaceDifference d;
  double sum = 0;
  for (int j = 0; j < cam.height(); ++j)
  {
    for (int i = 0; i < cam.width(); ++i)
    {
      const std::size_t p = static_cast<std::size_t>(j) * cam.width() + i;
      const bool wanted = expected.depth[p] < 1.0, shown = t[p] >= 0;
      d.onlyOne += wanted != shown;
      if (wanted && shown)
      {
        const ref::PixelRay ray = cam.ray(i, j);
        const double tRef = norm(cam.pointAt(i, j, expected.depth[p]) - ray.origin);
        const double e = std::fabs(t[p] - tRef) / radius;
        d.worst = std::max(d.worst, e);
        sum += e;
        ++d.both;
      }
    }
  }
  d.mean = d.both ? sum / d.both : 0;
  return d;
}

// The surface of the window's depth buffer as distances along the rays.
std::vector<double> FromDepthBuffer(vtkRenderWindow* win, const ref::ReferenceCamera& cam)
{
  std::vector<float> z(static_cast<std::size_t>(cam.width()) * cam.height());
  win->GetZbufferData(0, 0, cam.width() - 1, cam.height() - 1, z.data());
  std::vector<double> t(z.size(), -1);
  for (int j = 0; j < cam.height(); ++j)
  {
    for (int i = 0; i < cam.width(); ++i)
    {
      const std::size_t p = static_cast<std::size_t>(j) * cam.width() + i;
      if (z[p] < 1.f)
      {
        t[p] = norm(cam.pointAt(i, j, z[p]) - cam.ray(i, j).origin);
      }
    }
  }
  return t;
}

// The voxelizer's first entry as distances along the rays: zeta is measured from the eye
// plane, so the near-plane point (zeta = near) is subtracted.
std::vector<double> FromVoxelizer(vtkImageData* image,
  const ref::ReferenceCamera& cam,
  double nearPlane)
{
  vtkDataArray* entry = image->GetPointData()->GetArray("EntryDepth");
  vtkDataArray* scale = image->GetPointData()->GetArray("DepthToDistance");
  vtkDataArray* count = image->GetPointData()->GetArray("SpanCount");
  std::vector<double> t(static_cast<std::size_t>(cam.width()) * cam.height(), -1);
  for (std::size_t p = 0; p < t.size(); ++p)
  {
    if (count->GetTuple1(p) > 0)
    {
      t[p] = (entry->GetComponent(p, 0) - nearPlane) * scale->GetTuple1(p);
    }
  }
  return t;
}

bool Report(const char* what,
  const SurfaceDifference& d,
  int onlyOneBound,
  double worstBound,
  double meanBound)
{
  const bool pass =
    d.both > 5000 && d.onlyOne <= onlyOneBound && d.worst <= worstBound && d.mean <= meanBound;
  std::printf("%s %s: %d pixels covered by both, %d by one only (<= %d); distance between the "
              "surfaces %.4f radii at most (<= %.4f), %.4f on average (<= %.4f)\n",
    pass ? "ok  " : "FAIL",
    what,
    d.both,
    d.onlyOne,
    onlyOneBound,
    d.worst,
    worstBound,
    d.mean,
    meanBound);
  return pass;
}
}

int TestSPHFluidMapperReference(int argc, char* argv[])
{
  char* file = vtkTestUtilities::ExpandDataFileName(argc, argv, "dam_break_coarse_00674.vtk");
  vtkNew<vtkPolyDataReader> reader;
  reader->SetFileName(file);
  reader->ReadAllScalarsOn();
  reader->Update();
  delete[] file;
  vtkPolyData* particles = reader->GetOutput();
  RM_CHECK(particles->GetNumberOfPoints() == 9360);
  const double radius = 0.8 * particles->GetPointData()->GetArray("h")->GetTuple1(0);

  vtkNew<vtkSPHFluidMapper> mapper;
  mapper->SetInputData(particles);
  mapper->SetRadius(radius);
  mapper->TranslucencyOff();
  mapper->SetSmoothingRadius(0); // the reference has the union of the spheres, unsmoothed
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(vtkNew<vtkVolumeProperty>());
  vtkNew<vtkRenderer> ren;
  ren->AddVolume(volume);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(200, 150);
  win->AddRenderer(ren);
  vtkCamera* camera = ren->GetActiveCamera();
  camera->SetFocalPoint(0.9, 0.0, 0.2);
  camera->SetPosition(0.2, -2.6, 1.5);
  camera->SetViewUp(0, 0, 1);
  ren->ResetCameraClippingRange();
  win->Render();

  const ref::ReferenceCamera cam = ref::cameraOf(ren);
  std::vector<ref::ReferenceSphere> spheres;
  for (vtkIdType i = 0; i < particles->GetNumberOfPoints(); ++i)
  {
    double x[3];
    particles->GetPoint(i, x);
    spheres.push_back({ { x[0], x[1], x[2] }, radius, { 1, 1, 1 } });
  }
  const ref::ReferenceImage expected = ref::renderUnionSurface(cam, spheres);

  bool ok = Report("mapper, defaults (opaque)",
    Compare(cam, expected, FromDepthBuffer(win, cam), radius),
    5,
    0.11,
    0.042);
  mapper->SetAngleResolution(7);
  win->Render();
  ok = Report("mapper, AngleResolution 7",
         Compare(cam, expected, FromDepthBuffer(win, cam), radius),
         5,
         0.055,
         0.021) &&
       ok;
  mapper->SetAngleResolution(3);
  win->Render();
  ok = Report("mapper, AngleResolution 3",
         Compare(cam, expected, FromDepthBuffer(win, cam), radius),
         5,
         0.024,
         0.009) &&
       ok;

  vtkNew<vtkSPHVoxelizer> voxelizer;
  voxelizer->SetInputData(particles);
  voxelizer->SetRadius(radius);
  voxelizer->SetImageSize(cam.width(), cam.height());
  voxelizer->SetCamera(camera);
  voxelizer->ResetCameraOff();
  voxelizer->Update();
  ok = Report("vtkSPHVoxelizer, defaults",
         Compare(cam,
           expected,
           FromVoxelizer(voxelizer->GetOutput(), cam, camera->GetClippingRange()[0]),
           radius),
         5,
         0.11,
         0.042) &&
       ok;
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
