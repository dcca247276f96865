// vtkSPHVoxelizer on closed-form cases: one sphere of radius 1 seen from z = 5 by the
// filter's own camera (perspective, then parallel): the pixels with a span are those whose
// ray meets the sphere, the central pixel's entry and exit are the analytic depths 4 and 6
// within one layer, its Thickness is 2 and its normals face +z (entry) and -z (exit); two
// spheres one behind the other give two spans with their own-column links; bad particles
// are skipped with a warning; an empty input gives an image without spans.
// Usage: TestSPHVoxelizerFilter
#include "vtkSPHVoxelizer.h"

#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <array>
#include <limits>
#include <string>
#include <vector>

namespace
{
int Failures = 0;

void Check(bool ok, const std::string& what)
{
  std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
  Failures += ok ? 0 : 1;
}

void CountWarnings(vtkObject*, unsigned long, void* clientData, void*)
{
  ++*static_cast<int*>(clientData);
}

vtkNew<vtkPolyData> Spheres(const std::vector<std::array<double, 4>>& spheres)
{
  vtkNew<vtkPolyData> pd;
  vtkNew<vtkPoints> pts;
  vtkNew<vtkDoubleArray> r;
  r->SetName("r");
  for (const auto& s : spheres)
  {
    pts->InsertNextPoint(s[0], s[1], s[2]);
    r->InsertNextValue(s[3]);
  }
  pd->SetPoints(pts);
  pd->GetPointData()->AddArray(r);
  return pd;
}

double Field(vtkImageData* image, const char* name)
{
  return image->GetFieldData()->GetArray(name)->GetTuple1(0);
}
}

int main()
{
  // One sphere, the filter's camera on +z looking at it, fitted by ResetCamera: the
  // distance is then 1 / sin(15 deg) = 3.864 for the default 30 degree view angle.
  auto one = Spheres({ { 0, 0, 0, 1.0 } });
  vtkNew<vtkSPHVoxelizer> vox;
  vox->SetInputData(one);
  vox->SetScaleArray("r");
  vox->SetImageSize(61, 61);
  vox->SetCameraPosition(0, 0, 5);
  vox->SetCameraFocalPoint(0, 0, 0);
  vox->ResetCameraOff();
  vox->SetAngleResolution(2.0);
  vox->Update();
  vtkImageData* out = vox->GetOutput();
  int dims[3];
  out->GetDimensions(dims);
  Check(dims[0] == 61 && dims[1] == 61 && dims[2] == 1, "the image has the size asked for");
  vtkPointData* pd = out->GetPointData();
  for (const char* name : { "SpanCount", "SpansFound", "EntryDepth", "ExitDepth", "HiddenEmpty",
         "Thickness", "DepthToDistance", "EntryNormal", "ExitNormal", "Links" })
  {
    Check(pd->GetArray(name) != nullptr, std::string("array ") + name);
  }
  Check(pd->GetArray("EntryDepth")->GetNumberOfComponents() == 7 &&
      pd->GetArray("EntryNormal")->GetNumberOfComponents() == 21 &&
      pd->GetArray("Links")->GetNumberOfComponents() == 14,
    "S = 7 components per span array");
  // The pixels whose centre ray meets the sphere: the view's half angle is 15 degrees, so
  // pixel (i, j)'s ray has slope tan(15) (2 (i + 0.5) / 61 - 1) in x; it meets the unit
  // sphere at distance 5 when the angle to the axis is below asin(1 / 5).
  const double t = std::tan(15.0 * M_PI / 180.0), limit = std::asin(0.2);
  int expected = 0, agree = 0, got = 0;
  for (int j = 0; j < 61; ++j)
  {
    for (int i = 0; i < 61; ++i)
    {
      const double x = t * (2.0 * (i + 0.5) / 61 - 1), y = t * (2.0 * (j + 0.5) / 61 - 1);
      const bool hit = std::atan(std::sqrt(x * x + y * y)) < limit;
      const int c = static_cast<int>(pd->GetArray("SpanCount")->GetTuple1(j * 61 + i));
      expected += hit;
      got += c > 0;
      agree += hit == (c == 1);
    }
  }
  std::printf("pixels with a span %d, analytic %d, agreeing %d of %d\n", got, expected, agree,
    61 * 61);
  Check(agree >= 61 * 61 - 4 && expected > 400, "the pixels with a span are the sphere's (edge pixels aside)");
  const vtkIdType centre = 30 * 61 + 30;
  const double entry = pd->GetArray("EntryDepth")->GetComponent(centre, 0);
  const double exit = pd->GetArray("ExitDepth")->GetComponent(centre, 0);
  const double layer = 5.0 * std::tan(15.0 * M_PI / 180.0) * 2 / 61 * std::tan(2.0 * M_PI / 180.0);
  std::printf("centre: entry %.5f exit %.5f (4, 6; layer about %.5f), thickness %.5f\n", entry, exit,
    layer, pd->GetArray("Thickness")->GetTuple1(centre));
  Check(entry <= 4.0 + 1e-5 && entry > 4.0 - 1.5 * layer && exit >= 6.0 - 1e-5 &&
      exit < 6.0 + 1.5 * 1.2 * layer,
    "the central entry and exit are 4 and 6 within one layer");
  Check(std::abs(pd->GetArray("Thickness")->GetTuple1(centre) - 2.0) < 3 * layer,
    "the central thickness is 2r");
  Check(std::isnan(pd->GetArray("EntryDepth")->GetComponent(centre, 1)), "unused slots are NaN");
  {
    // An oblique ray (pixel (50, 30), angle theta to the axis): the chord it cuts from the
    // sphere is 2 sqrt(1 - (5 sin theta)^2) in world units.
    const double theta = std::atan(t * (2.0 * 50.5 / 61 - 1));
    const double chord = 2 * std::sqrt(1 - std::pow(5 * std::sin(theta), 2));
    const double got50 = pd->GetArray("Thickness")->GetTuple1(30 * 61 + 50);
    std::printf("oblique pixel: thickness %.5f, chord %.5f\n", got50, chord);
    Check(std::abs(got50 - chord) < 0.005, "an oblique pixel's thickness is the world chord");
  }
  Check(pd->GetArray("EntryNormal")->GetComponent(centre, 2) > 0.99,
    "entry normal faces the camera (+z)");
  Check(pd->GetArray("ExitNormal")->GetComponent(centre, 2) < -0.99, "exit normal faces away (-z)");
  Check(Field(out, "LayerCount") > 100 && Field(out, "LogarithmicLayers") == 1 &&
      Field(out, "AngleResolutionReached") <= 2.0 + 1e-6,
    "the layers keep the angle resolution");
  const std::string summary = vox->GetStatisticsSummary();
  Check(summary.find("counter spans_stored") != std::string::npos, "statistics summary");

  // Parallel projection with ResetCamera: the sphere fills a disk of the parallel scale.
  vox->SetCameraParallelProjection(true);
  vox->ResetCameraOn();
  vox->Update();
  out = vox->GetOutput();
  pd = out->GetPointData();
  int disk = 0;
  for (vtkIdType p = 0; p < 61 * 61; ++p)
  {
    disk += pd->GetArray("SpanCount")->GetTuple1(p) > 0;
  }
  // Radius 1 inside a view of half height sqrt(3) (the bounds' half diagonal).
  const double area = M_PI * std::pow(61.0 / (2 * std::sqrt(3.0)), 2);
  std::printf("parallel: %d pixels, disk %.1f; thickness %.4f\n", disk, area,
    pd->GetArray("Thickness")->GetTuple1(centre));
  Check(std::abs(disk - area) < 0.05 * area, "parallel view: a disk of the sphere's radius");
  Check(std::abs(pd->GetArray("Thickness")->GetTuple1(centre) - 2.0) < 0.05,
    "parallel view: central thickness 2r");

  // Two spheres on the axis: two spans in the centre, the boundary spans' entry and exit
  // link to each other in their own column only where no neighbour overlaps.
  auto two = Spheres({ { 0, 0, 0.8, 0.5 }, { 0, 0, -0.8, 0.5 } });
  vtkNew<vtkSPHVoxelizer> vox2;
  vox2->SetInputData(two);
  vox2->SetScaleArray("r");
  vox2->SetImageSize(41, 41);
  vox2->SetCameraPosition(0, 0, 5);
  vox2->Update();
  pd = vox2->GetOutput()->GetPointData();
  const vtkIdType c2 = 20 * 41 + 20;
  Check(pd->GetArray("SpanCount")->GetTuple1(c2) == 2 && pd->GetArray("SpansFound")->GetTuple1(c2) == 2,
    "two spheres one behind the other: two spans");
  const unsigned int link = static_cast<unsigned int>(pd->GetArray("Links")->GetComponent(c2, 0));
  Check((link & 0xFF) == 0 && ((link >> 8) & 0xFF) == 0,
    "the central entry links to the neighbours' first entries (+x, -x)");
  vox2->SetMaximumSpans(1);
  vox2->Update();
  pd = vox2->GetOutput()->GetPointData();
  const double hiddenThickness = pd->GetArray("Thickness")->GetTuple1(c2);
  std::printf("one span kept: thickness %.4f, hidden %.4f\n", hiddenThickness,
    pd->GetArray("HiddenEmpty")->GetTuple1(c2));
  Check(pd->GetArray("SpanCount")->GetTuple1(c2) == 1 && pd->GetArray("SpansFound")->GetTuple1(c2) == 2 &&
      std::abs(hiddenThickness - 2.0) < 0.05,
    "one span kept: the thickness stays 2 x 2r (the gap is hidden empty space)");

  // Bad particles and empty input.
  int warnings = 0;
  vtkNew<vtkCallbackCommand> cb;
  cb->SetCallback(CountWarnings);
  cb->SetClientData(&warnings);
  vox->AddObserver(vtkCommand::WarningEvent, cb);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto bad = Spheres({ { 0, 0, 0, 1.0 }, { nan, 0, 0, 1.0 }, { 0.5, 0, 0, -1.0 } });
  vox->SetInputData(bad);
  vox->Update();
  Check(warnings == 2 && vox->GetOutput()->GetPointData()->GetArray("Thickness")->GetTuple1(centre) > 1.9,
    "NaN position and negative radius: two warnings, the good sphere voxelized");
  vtkNew<vtkPolyData> empty;
  vox->SetInputData(empty);
  vox->Update();
  double range[2];
  vox->GetOutput()->GetPointData()->GetArray("SpanCount")->GetRange(range);
  Check(warnings == 3 && range[1] == 0, "empty input: a warning, no spans");
  return Failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
