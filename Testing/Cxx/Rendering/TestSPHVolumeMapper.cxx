// vtkSPHVolumeMapper on a PySPH dam break (Data/dam_break_coarse_00674.vtk, t = 0.3 s):
// the velocity magnitude volume rendered with PySPH's own kernel (Wendland C2, support 2h)
// and V = m / rho; the normalized picture does not depend on a constant scale of the
// volumes; shading and contours cost nothing when off; an opaque sphere stops the rays;
// interaction reduces the sampling rate and a still render refines back to the same
// picture; the picture matches the baseline.
//
// usage: TestSPHVolumeMapper -D <Data dir> -T <tmp> -V <png>
#include "RenderingTestHelpers.h"
#include "vtkRayMapperStatistics.h"
#include "vtkSPHVolumeMapper.h"

#include "vtkActor.h"
#include "vtkColorTransferFunction.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPolyDataMapper.h"
#include "vtkPolyDataReader.h"
#include "vtkProperty.h"
#include "vtkSphereSource.h"
#include "vtkTestUtilities.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>

namespace
{
double MeanDifference(const std::vector<unsigned char>& a, const std::vector<unsigned char>& b)
{
  double sum = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
  {
    sum += std::abs(int(a[k]) - int(b[k]));
  }
  return sum / static_cast<double>(a.size());
}
}

int TestSPHVolumeMapper(int argc, char* argv[])
{
  char* file = vtkTestUtilities::ExpandDataFileName(argc, argv, "dam_break_coarse_00674.vtk");
  vtkNew<vtkPolyDataReader> reader;
  reader->SetFileName(file);
  reader->ReadAllScalarsOn(); // the file has one SCALARS section per array
  reader->Update();
  delete[] file;
  vtkPolyData* particles = reader->GetOutput();
  if (particles->GetNumberOfPoints() != 9360)
  {
    std::printf("FAIL: the dam break was not read\n");
    return EXIT_FAILURE;
  }

  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 0.1, 0.3, 0.9);
  color->AddRGBPoint(1.4, 0.9, 0.9, 0.9);
  color->AddRGBPoint(2.8, 0.9, 0.2, 0.1);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.15);
  opacity->AddPoint(2.8, 0.6);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(0.1);

  vtkNew<vtkSPHVolumeMapper> mapper;
  mapper->SetInputData(particles);
  mapper->SetKernel(VTK_SPH_KERNEL_WENDLAND_C2);
  mapper->SetSmoothingLengthArrayName("h");
  mapper->SetMassArrayName("m");
  mapper->SetDensityArrayName("rho");
  mapper->SetValueArrayName("vmag");
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> ren;
  ren->SetBackground(0.1, 0.1, 0.15);
  ren->AddVolume(volume);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(400, 300);
  win->AddRenderer(ren);
  rmtest::EventCounter events;
  events.Observe(mapper);
  // From the side and above, z up: the collapsing column on the left, the surge front on
  // the right.
  vtkCamera* camera = ren->GetActiveCamera();
  camera->SetFocalPoint(0.9, 0.0, 0.2);
  camera->SetPosition(0.2, -2.6, 1.5);
  camera->SetViewUp(0, 0, 1);
  ren->ResetCameraClippingRange();

  bool ok = true;
  auto check = [&](bool condition, const char* what) {
    std::printf("%s %s\n", condition ? "ok  " : "FAIL", what);
    ok = ok && condition;
  };
  auto render = [&]() {
    win->Render();
    return rmtest::ReadRGB(win);
  };
  vtkRayMapperStatistics* stats = mapper->GetStatistics();

  const auto picture = render();
  const auto fullBundles = stats->GetCounter("bundles");
  std::printf("%s", stats->GetSummary());
  check(stats->GetCounter("particles") == 9360 && events.Warnings == 0 && events.Errors == 0,
    "every particle used, no warning");
  check(stats->GetCounter("weight_sums") == stats->GetCounter("kernel_evaluations") &&
      stats->GetCounter("gradient_evaluations") == 0 && stats->GetCounter("contour_samples") == 0,
    "normalized: weights summed; no gradient or contour work when they are off");

  // A constant volume: the normalized field does not depend on its scale.
  mapper->SetMassArrayName(nullptr);
  mapper->SetDensityArrayName(nullptr);
  mapper->SetVolume(6.4e-5);
  const auto constant = render();
  mapper->SetVolume(1.0);
  const auto scaled = render();
  std::printf("constant volume: %.4f from m/rho, %.4f from a 15625x larger one\n",
    MeanDifference(constant, picture), MeanDifference(scaled, constant));
  check(MeanDifference(scaled, constant) < 0.01, "normalized picture independent of the volumes' scale");
  check(MeanDifference(constant, picture) < 1.0, "V = m/rho within 3% of constant: nearly the same picture");
  mapper->SetMassArrayName("m");
  mapper->SetDensityArrayName("rho");

  // Shading and contours, each on alone.
  property->ShadeOn();
  property->SetAmbient(0.3);
  property->SetDiffuse(0.7);
  const auto shaded = render();
  check(stats->GetCounter("gradient_evaluations") == stats->GetCounter("kernel_evaluations") &&
      stats->GetCounter("shaded_samples") > 0 && MeanDifference(shaded, picture) > 1.0,
    "gradient shading on: exact gradients with every kernel evaluation, a different picture");
  property->ShadeOff();
  mapper->ContourShadingOn();
  const auto contoured = render();
  check(stats->GetCounter("contour_samples") > 0 && stats->GetCounter("gradient_evaluations") == 0 &&
      MeanDifference(contoured, picture) > 1.0,
    "contour shading on: contour samples, no gradients");
  mapper->ContourShadingOff();

  // An opaque sphere in front of the water column stops the rays.
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(0.4, -0.2, 0.25);
  sphere->SetRadius(0.12);
  sphere->SetThetaResolution(32);
  sphere->SetPhiResolution(32);
  vtkNew<vtkPolyDataMapper> sphereMapper;
  sphereMapper->SetInputConnection(sphere->GetOutputPort());
  vtkNew<vtkActor> actor;
  actor->SetMapper(sphereMapper);
  actor->GetProperty()->SetColor(1, 1, 0);
  ren->AddActor(actor);
  const auto occluded = render();
  check(stats->GetCounter("cells_visited") > 0 && MeanDifference(occluded, picture) > 0.5,
    "the sphere shows");
  ren->RemoveActor(actor);

  // Interaction: under a 1 ns budget the last frame's time asks for a sample distance far
  // above the maximum, so the maximum it is (a budget the machine's speed cannot meet);
  // a still render goes back to the full picture; a fixed distance holds in both.
  mapper->SetMaximumImageSampleDistance(3.0);
  win->SetDesiredUpdateRate(1e9);
  const auto coarse = render();
  const auto reduction = stats->GetCounter("reduction_percent");
  std::printf("interactive: reduction %lld%%, difference %.3f\n", static_cast<long long>(reduction),
    MeanDifference(coarse, picture));
  check(reduction == 300 && stats->GetCounter("image_sample_distance_percent") == 300 &&
      MeanDifference(coarse, picture) > 0,
    "reduced sampling while interacting: MaximumImageSampleDistance");
  // 3 x 3 fewer rays: the coarse frame's 16 x 16 bundles are about a ninth of the full one's.
  std::printf("bundles: full %lld, coarse %lld\n", static_cast<long long>(fullBundles),
    static_cast<long long>(stats->GetCounter("bundles")));
  check(fullBundles > 0 && 4 * stats->GetCounter("bundles") < fullBundles,
    "the interactive frame casts 3 x 3 fewer rays");
  win->SetDesiredUpdateRate(0.0001);
  const auto refined = render();
  check(stats->GetCounter("reduction_percent") == 100 && refined == picture,
    "a still render refines to the full picture");
  mapper->AutoAdjustSampleDistancesOff();
  mapper->SetImageSampleDistance(2.0);
  const auto fixed = render();
  check(stats->GetCounter("image_sample_distance_percent") == 200 && fixed != picture,
    "AutoAdjustSampleDistances off: ImageSampleDistance in a still render too");
  mapper->AutoAdjustSampleDistancesOn();
  mapper->SetMaximumReduction(4.0); // the deprecated alias
  check(mapper->GetMaximumImageSampleDistance() == 4.0 && render() == picture,
    "MaximumReduction sets MaximumImageSampleDistance; still renders stay full");

  check(rmtest::CompareWithBaseline(win, argc, argv) == EXIT_SUCCESS, "matches the baseline");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
