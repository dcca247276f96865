// Bad input to vtkRBFVolumeMapper gets a clear warning and loses nothing else: an empty
// input draws nothing, missing value/radius/field arrays fall back with a warning, and
// particles with NaN coordinates or values or bad radii are skipped (one warning each kind)
// while the picture of the valid particles stays exactly the same, with no NaN anywhere.
#include "RenderingTestHelpers.h"
#include "vtkRBFVolumeMapper.h"
#include "vtkRayMapperStatistics.h"

#include "vtkColorTransferFunction.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <limits>

namespace
{
struct Viewer
{
  vtkNew<vtkRBFVolumeMapper> Mapper;
  vtkNew<vtkVolumeProperty> Property;
  vtkNew<vtkVolume> Volume;
  vtkNew<vtkRenderer> Ren;
  vtkNew<vtkRenderWindow> Win;
  rmtest::EventCounter Events;
  Viewer()
  {
    vtkNew<vtkColorTransferFunction> color;
    color->AddRGBPoint(0, 0.2, 0.3, 0.9);
    color->AddRGBPoint(1.5, 1.0, 0.8, 0.2);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(0, 0);
    opacity->AddPoint(1.5, 0.8);
    Property->SetColor(color);
    Property->SetScalarOpacity(opacity);
    Property->SetScalarOpacityUnitDistance(0.3);
    Mapper->SetSampleDistance(0.05);
    Volume->SetMapper(Mapper);
    Volume->SetProperty(Property);
    Ren->AddVolume(Volume);
    Win->SetSize(120, 120);
    Win->AddRenderer(Ren);
    Ren->GetActiveCamera()->SetPosition(0.5, 0.7, 6);
    Ren->GetActiveCamera()->SetFocalPoint(0, 0, 0);
    Ren->GetActiveCamera()->SetViewAngle(40);
    Events.Observe(Mapper);
  }
  std::vector<unsigned char> Show(vtkPolyData* data)
  {
    Mapper->SetInputData(data);
    Ren->ResetCameraClippingRange(-3, 3, -3, 3, -3, 3);
    Win->Render();
    return rmtest::ReadRGB(Win);
  }
};
}

int TestRBFBadInput(int, char*[])
{
  auto clean = rmtest::MakeLattice(4);
  Viewer v;
  v.Mapper->SetRadiusArrayName("radius");
  v.Mapper->SetRadiusScale(2.0);
  const auto reference = v.Show(clean);
  RM_CHECK(v.Events.Warnings == 0 && v.Events.Errors == 0);

  // NaN coordinates, NaN value, zero / negative / NaN radius: 5 particles more, skipped.
  std::vector<std::array<double, 3>> c;
  std::vector<double> r;
  for (vtkIdType i = 0; i < clean->GetNumberOfPoints(); ++i)
  {
    std::array<double, 3> p;
    clean->GetPoint(i, p.data());
    c.push_back(p);
    r.push_back(clean->GetPointData()->GetArray("radius")->GetComponent(i, 0));
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  c.push_back({ nan, 0, 0 });
  r.push_back(0.2);
  for (const double bad : { 0.0, -0.3, nan })
  {
    c.push_back({ 0.1, 0.2, 0.3 });
    r.push_back(bad);
  }
  c.push_back({ 0.3, 0.1, 0.0 });
  r.push_back(0.2);
  auto dirty = rmtest::MakeSpheres(c, r);
  // "value" holds each point's index; the last point's value is NaN.
  dirty->GetPointData()->GetArray("value")->SetComponent(c.size() - 1, 0, nan);
  v.Mapper->SetValueArrayName("value");
  // With values the picture changes; compare dirty against clean with the same setting.
  const auto cleanValued = v.Show(clean);
  v.Events.Warnings = 0;
  const auto dirtyValued = v.Show(dirty);
  RM_CHECK(dirtyValued == cleanValued);
  RM_CHECK(v.Events.Warnings == 2); // non-finite coordinates/values, bad radii
  RM_CHECK(v.Mapper->GetStatistics()->GetCounter("particles") == clean->GetNumberOfPoints());
  v.Mapper->SetValueArrayName(nullptr);

  // Missing arrays: one warning each, the fallbacks draw.
  v.Events.Warnings = 0;
  v.Mapper->SetRadiusArrayName("no-such-radius");
  v.Mapper->SetValueArrayName("no-such-value");
  v.Mapper->SetFieldArrayName("no-such-field");
  const auto fallback = v.Show(clean);
  RM_CHECK(v.Events.Warnings == 3);
  RM_CHECK(fallback != reference); // the constant radius 1 x 2 is not the lattice's radii
  v.Mapper->SetRadiusArrayName("radius");
  v.Mapper->SetValueArrayName(nullptr);
  v.Mapper->SetFieldArrayName(nullptr);
  RM_CHECK(v.Show(clean) == reference);

  // An empty input: a warning, nothing drawn, no crash.
  v.Events.Warnings = 0;
  vtkNew<vtkPolyData> empty;
  const auto nothing = v.Show(empty);
  RM_CHECK(v.Events.Warnings == 1);
  RM_CHECK(std::all_of(nothing.begin(), nothing.end(), [](unsigned char x) { return x == 0; }));

  // Absurd parameters are clamped, never NaN.
  v.Mapper->SetSigma(-5);
  v.Mapper->SetKappa(-1);
  v.Mapper->SetSamplesPerPass(100000);
  v.Show(clean);
  RM_CHECK(v.Mapper->GetSigma() == 0.0 && v.Mapper->GetKappa() == 0.0);
  RM_CHECK(v.Mapper->GetSamplesPerPass() == 256);
  return EXIT_SUCCESS;
}
