// Bad input gets a clear warning and loses nothing else: an empty input, points with NaN
// coordinates, zero / negative / NaN radii and a missing radius array each render exactly
// the picture of the valid part of the data, with a warning and no crash.
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"
#include "vtkRayMapperStatistics.h"

#include "vtkActor.h"
#include "vtkProperty.h"

#include <limits>

namespace
{
struct Viewer
{
  vtkNew<vtkCGTSphereMapper> Mapper;
  vtkNew<vtkActor> Actor;
  vtkNew<vtkRenderer> Ren;
  vtkNew<vtkRenderWindow> Win;
  rmtest::EventCounter Events;
  Viewer()
  {
    Mapper->SetScalarRange(0, 30);
    Actor->SetMapper(Mapper);
    Ren->AddActor(Actor);
    Win->SetSize(160, 160);
    Win->AddRenderer(Ren);
    Ren->GetActiveCamera()->SetPosition(0.5, 0.7, 6);
    Ren->GetActiveCamera()->SetFocalPoint(0, 0, 0);
    Ren->GetActiveCamera()->SetViewAngle(40);
    Ren->SetNearClippingPlaneTolerance(1e-4);
    Events.Observe(Mapper);
  }
  std::vector<unsigned char> Show(vtkPolyData* data)
  {
    Mapper->SetInputData(data);
    Ren->ResetCameraClippingRange(-2, 2, -2, 2, -2, 2);
    Win->Render();
    return rmtest::ReadRGB(Win);
  }
};

vtkSmartPointer<vtkPolyData> WithExtraPoints(vtkPolyData* clean,
  const std::vector<std::array<double, 3>>& points,
  const std::vector<double>& radii)
{
  std::vector<std::array<double, 3>> c;
  std::vector<double> r;
  for (vtkIdType i = 0; i < clean->GetNumberOfPoints(); ++i)
  {
    std::array<double, 3> p;
    clean->GetPoint(i, p.data());
    c.push_back(p);
    r.push_back(clean->GetPointData()->GetArray("radius")->GetComponent(i, 0));
  }
  c.insert(c.end(), points.begin(), points.end());
  r.insert(r.end(), radii.begin(), radii.end());
  auto out = rmtest::MakeSpheres(c, r);
  // Keep the colours of the clean points: the extra points get values past the range.
  return out;
}
}

int TestSpheresBadInput(int, char*[])
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto clean = rmtest::MakeLattice(3);

  Viewer reference;
  reference.Mapper->SetRadiusArrayName("radius");
  const auto expected = reference.Show(clean);
  RM_CHECK(reference.Events.Warnings == 0);

  // Empty input: a warning, nothing drawn, the background only.
  {
    Viewer v;
    vtkNew<vtkPolyData> empty;
    const auto img = v.Show(empty);
    RM_CHECK(v.Events.Warnings >= 1);
    RM_CHECK(v.Events.Errors == 0);
    for (unsigned char c : img)
    {
      RM_CHECK(c == 0);
    }
  }
  // NaN and infinite coordinates: one warning, the other spheres exactly as without them.
  {
    Viewer v;
    v.Mapper->SetRadiusArrayName("radius");
    auto data = WithExtraPoints(
      clean, { { nan, 0, 0 }, { 0, inf, 0 }, { nan, nan, nan } }, { 0.3, 0.3, 0.3 });
    RM_CHECK(v.Show(data) == expected);
    RM_CHECK(v.Events.Warnings == 1);
    RM_CHECK(v.Mapper->GetStatistics()->GetCounter("spheres") == 27);
  }
  // Zero, negative, NaN radii: dropped with one warning.
  {
    Viewer v;
    v.Mapper->SetRadiusArrayName("radius");
    auto data = WithExtraPoints(
      clean, { { 0.5, 0.5, 0.5 }, { -0.5, 0.5, 0 }, { 0, 0, 0.5 } }, { 0.0, -0.2, nan });
    RM_CHECK(v.Show(data) == expected);
    RM_CHECK(v.Events.Warnings == 1);
  }
  // A radius array that does not exist: a warning naming it, the constant radius used,
  // the picture of the constant radius.
  {
    Viewer constant;
    constant.Mapper->SetRadius(0.2);
    const auto withConstant = constant.Show(clean);
    Viewer v;
    v.Mapper->SetRadius(0.2);
    v.Mapper->SetRadiusArrayName("no_such_array");
    RM_CHECK(v.Show(clean) == withConstant);
    RM_CHECK(v.Events.Warnings == 1);
    RM_CHECK(v.Events.Last.find("no_such_array") != std::string::npos);
  }
  // An absurd constant radius (negative) or scale: nothing drawn, a warning, no crash.
  {
    Viewer v;
    v.Mapper->SetRadius(-1);
    v.Show(clean);
    RM_CHECK(v.Events.Warnings == 1);
    RM_CHECK(v.Mapper->GetStatistics()->GetCounter("spheres") == 0);
  }
  std::printf("bad input: all cases handled\n");
  return EXIT_SUCCESS;
}
