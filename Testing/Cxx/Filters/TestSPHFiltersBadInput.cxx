// vtkSPHVoxelizer and vtkSPHBoundaryParticles on bad input. Each case gives exactly the
// warnings it names (each naming its problem) and an output exactly equal (every point array
// bit for bit, NaN equal to NaN) to the output of the input without the bad part:
//   - particles with NaN / infinite positions and zero / negative / NaN / infinite / huge
//     radii; a missing radius array (the constant radius); an integer radius array (silent);
//     a 3-component radius array (one warning, its first component); an empty input;
//   - NaN, negative and huge property values (one warning each; NaN keeps the value, the
//     others are clamped: the output of the bound set directly), the voxelizer's camera
//     settings included;
//   - the voxelizer's degenerate cameras (the eye at the focal point, with and without
//     Reset Camera): one warning, no spans, finite Thickness and DepthToDistance.
// Usage: TestSPHFiltersBadInput
#include "vtkSPHBoundaryParticles.h"
#include "vtkSPHVoxelizer.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace
{
int Failures = 0;
std::vector<std::string> Messages; // the filters' warnings and errors, in order
std::size_t Mark = 0;

void Check(bool ok, const std::string& what)
{
  std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
  Failures += ok ? 0 : 1;
}

void Record(vtkObject*, unsigned long event, void*, void* text)
{
  const std::string t = text ? static_cast<const char*>(text) : "";
  std::printf("observed %s: %s\n", event == vtkCommand::WarningEvent ? "warning" : "error",
    t.c_str());
  Messages.push_back((event == vtkCommand::WarningEvent ? "" : "ERROR ") + t);
}

/// Exactly n messages since the last call, all warnings containing `text`.
void Warned(int n, const std::string& text, const std::string& what)
{
  bool named = true;
  for (std::size_t k = Mark; k < Messages.size(); ++k)
  {
    named = named && Messages[k].find(text) != std::string::npos &&
      Messages[k].rfind("ERROR", 0) != 0;
  }
  const std::size_t seen = Messages.size() - Mark;
  Mark = Messages.size();
  Check(static_cast<int>(seen) == n && named,
    what + ": " + std::to_string(n) + " warning(s) naming '" + text + "' (saw " +
      std::to_string(seen) + ")");
}

void Observe(vtkObject* o)
{
  vtkNew<vtkCallbackCommand> cb;
  cb->SetCallback(Record);
  o->AddObserver(vtkCommand::WarningEvent, cb);
  o->AddObserver(vtkCommand::ErrorEvent, cb);
}

bool SameValue(double a, double b)
{
  return a == b || (std::isnan(a) && std::isnan(b));
}

/// Whether two outputs have the same points and point arrays, value for value.
bool SameOutput(vtkDataSet* a, vtkDataSet* b)
{
  if (a->GetNumberOfPoints() != b->GetNumberOfPoints())
  {
    return false;
  }
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    double p[3], q[3];
    a->GetPoint(i, p);
    b->GetPoint(i, q);
    if (p[0] != q[0] || p[1] != q[1] || p[2] != q[2])
    {
      return false;
    }
  }
  vtkPointData* pa = a->GetPointData();
  vtkPointData* pb = b->GetPointData();
  if (pa->GetNumberOfArrays() != pb->GetNumberOfArrays())
  {
    return false;
  }
  for (int k = 0; k < pa->GetNumberOfArrays(); ++k)
  {
    vtkDataArray* x = pa->GetArray(k);
    vtkDataArray* y = x && x->GetName() ? pb->GetArray(x->GetName()) : nullptr;
    if (!x || !y || x->GetNumberOfValues() != y->GetNumberOfValues())
    {
      return false;
    }
    const int c = x->GetNumberOfComponents();
    for (vtkIdType v = 0; v < x->GetNumberOfValues(); ++v)
    {
      if (!SameValue(x->GetComponent(v / c, v % c), y->GetComponent(v / c, v % c)))
      {
        return false;
      }
    }
  }
  return true;
}

template<typename Filter>
vtkSmartPointer<vtkDataSet> Run(Filter* filter)
{
  filter->Update();
  auto copy = vtkSmartPointer<vtkDataSet>::Take(filter->GetOutput()->NewInstance());
  copy->DeepCopy(filter->GetOutput());
  return copy;
}

/// A block of n^3 spheres of radius r at spacing 1 with an "r" array (and "ir", integer 1,
/// for RadiusScale r; "r3": (r, 2r, 0)) and a point array "id".
vtkSmartPointer<vtkPolyData> Block(int n, double r)
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  vtkNew<vtkDoubleArray> radius, r3;
  vtkNew<vtkIntArray> ir, id;
  radius->SetName("r");
  ir->SetName("ir");
  r3->SetName("r3");
  r3->SetNumberOfComponents(3);
  id->SetName("id");
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        id->InsertNextValue(static_cast<int>(pts->InsertNextPoint(i, j, k)));
        radius->InsertNextValue(r);
        ir->InsertNextValue(1);
        r3->InsertNextTuple3(r, 2 * r, 0);
      }
  pd->SetPoints(pts);
  for (vtkDataArray* a : { static_cast<vtkDataArray*>(radius), static_cast<vtkDataArray*>(ir),
         static_cast<vtkDataArray*>(r3), static_cast<vtkDataArray*>(id) })
  {
    pd->GetPointData()->AddArray(a);
  }
  return pd;
}

/// The block with 8 bad particles appended inside its bounds: 2 non-finite positions and
/// radii 0, -1, NaN, infinity, 1e20 and 1e300.
vtkSmartPointer<vtkPolyData> WithBadParticles(vtkPolyData* clean)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(clean);
  vtkPointData* pd = out->GetPointData();
  auto add = [&](double x, double y, double z, double r) {
    out->GetPoints()->InsertNextPoint(x, y, z);
    pd->GetArray("r")->InsertNextTuple1(r);
    pd->GetArray("ir")->InsertNextTuple1(1);
    pd->GetArray("r3")->InsertNextTuple3(r, r, r);
    pd->GetArray("id")->InsertNextTuple1(-1);
  };
  add(nan, 0, 0, 0.6);
  add(0, inf, 0, 0.6);
  for (const double r : { 0.0, -1.0, nan, inf, 1e20, 1e300 })
  {
    add(0.5, 0.5, 0.5, r);
  }
  return out;
}

/// The radius-array cases common to both filters (the block's radius is `radius`): bad
/// particles, a missing array, an integer and a 3-component array, an empty input.
template<typename Filter>
void RadiusCases(Filter* filter, vtkPolyData* clean, double radius, const char* name)
{
  const std::string who = name;
  filter->SetInputData(clean);
  filter->SetScaleArray("r");
  const auto reference = Run(filter);
  Warned(0, "", who + ": the clean block");

  filter->SetInputData(WithBadParticles(clean));
  Check(SameOutput(Run(filter), reference), who + ": bad particles: the output of the others");
  Warned(2, "particles have", who + ": bad particles (positions; radii)");

  filter->SetInputData(clean);
  filter->SetScaleArray("ir");
  filter->SetScaleFactor(radius);
  Check(SameOutput(Run(filter), reference), who + ": an integer radius array");
  Warned(0, "", who + ": an integer radius array");
  filter->SetScaleFactor(1);
  filter->SetScaleArray("r3");
  Check(SameOutput(Run(filter), reference), who + ": a 3-component radius array: the first");
  Warned(1, "radius array 'r3' has 3 components that differ: the first is used",
    who + ": a 3-component radius array");

  filter->SetScaleArray("no-such-radius");
  filter->SetRadius(radius);
  Check(SameOutput(Run(filter), reference), who + ": a missing radius array: the constant");
  Warned(1, "radius array 'no-such-radius' is not a point array", who + ": a missing array");
  filter->SetScaleArray("r");

  vtkNew<vtkPolyData> empty;
  empty->SetPoints(vtkNew<vtkPoints>());
  filter->SetInputData(empty);
  filter->Update();
  Warned(1, "no points", who + ": an empty input");
  filter->SetInputData(clean);
  Check(SameOutput(Run(filter), reference), who + ": the clean block again");
  Warned(0, "", who + ": the clean block again");
}

struct PropertyCase
{
  std::string name;
  std::function<void(double)> set;
  double good, bad, bound; // bad NaN: rejected; else clamped to bound
  std::string text;
  int boundWarnings = 0;
  std::string boundText = "";
};

/// NaN keeps the value (the output at `good`); out of range: the output at the bound.
template<typename Filter>
void PropertyCases(Filter* filter, const std::vector<PropertyCase>& cases, const char* name)
{
  for (const PropertyCase& c : cases)
  {
    const std::string what = std::string(name) + ": " + c.name;
    c.set(c.good);
    const auto atGood = Run(filter);
    Warned(0, "", what + " " + std::to_string(c.good));
    if (std::isnan(c.bad))
    {
      c.set(c.bad);
      Warned(1, "not a number", what + " NaN");
      Check(SameOutput(Run(filter), atGood), what + " NaN: the output before it");
    }
    else
    {
      c.set(c.bound);
      const auto atBound = Run(filter);
      Warned(c.boundWarnings, c.boundText, what + " at its bound");
      c.set(c.bad);
      Warned(1, c.text, what + " out of range");
      Check(SameOutput(Run(filter), atBound), what + " clamped: the output of the bound");
      Warned(0, "", what + " clamped, run");
    }
    c.set(c.good);
    Run(filter);
    Mark = Messages.size();
  }
}

bool FiniteEverywhere(vtkImageData* image, const char* name)
{
  vtkDataArray* a = image->GetPointData()->GetArray(name);
  for (vtkIdType v = 0; a && v < a->GetNumberOfValues(); ++v)
  {
    if (!std::isfinite(a->GetComponent(v, 0)))
    {
      return false;
    }
  }
  return a != nullptr;
}

void Voxelizer()
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto clean = Block(4, 0.6);
  vtkNew<vtkSPHVoxelizer> vox;
  Observe(vox);
  vox->SetImageSize(40, 32);
  vox->SetCameraPosition(1.5, 2, 12);
  vox->SetCameraFocalPoint(1.5, 1.5, 1.5);
  vox->ResetCameraOff();
  RadiusCases(vox.Get(), clean, 0.6, "voxelizer");
  vtkSPHVoxelizer* v = vox;
  PropertyCases(v,
    { { "Radius", [&](double x) { v->SetRadiusArrayName(nullptr), v->SetRadius(x); }, 0.6, nan, 0, "" },
      { "RadiusScale", [&](double x) { v->SetRadiusScale(x); }, 1, nan, 0, "" },
      { "AngleResolution", [&](double x) { v->SetAngleResolution(x); }, 14, nan, 0, "" },
      { "MemoryBudget", [&](double x) { v->SetMemoryBudget(x); }, 512, nan, 0, "" },
      { "GapThreshold", [&](double x) { v->SetGapThreshold(x); }, 0.3, nan, 0, "" },
      { "CellSize", [&](double x) { v->SetCellSize(x); }, 0, nan, 0, "" },
      { "SmoothingRadius", [&](double x) { v->SetSmoothingRadius(x); }, 0.3, nan, 0, "" },
      { "CameraPosition", [&](double x) { v->SetCameraPosition(1.5, 2, x); }, 12, nan, 0, "" },
      { "CameraViewAngle", [&](double x) { v->SetCameraViewAngle(x); }, 30, nan, 0, "" },
      { "Radius", [&](double x) { v->SetRadius(x); }, 0.6, -1, 0,
        "Radius -1 is outside [0, 1e+15]: clamped to 0", 0, "" }, // 0: automatic, kept
      { "MemoryBudget", [&](double x) { v->SetMemoryBudget(x); }, 512, -1, 0,
        "MemoryBudget -1 is outside [0, 1e+06]: clamped to 0", 0, "" }, // 0: automatic
      { "AngleResolution", [&](double x) { v->SetAngleResolution(x); }, 14, 0, 0.01,
        "AngleResolution 0 is outside [0.01, 89]" },
      { "MaximumSpans", [&](double x) { v->SetMaximumSpans(static_cast<int>(x)); }, 7, 100, 63,
        "MaximumSpans 100 is outside [1, 63]" },
      { "CameraViewAngle", [&](double x) { v->SetCameraViewAngle(x); }, 30, 500, 179,
        "CameraViewAngle 500 is outside" },
      { "ImageSize", [&](double x) { v->SetImageSize(static_cast<int>(x), 32); }, 40, -5, 1,
        "ImageSize has components outside [1, 16384]" } },
    "voxelizer");

  // Degenerate cameras: one warning, no spans, finite per-pixel values.
  for (const bool reset : { false, true })
  {
    const std::string what = std::string("voxelizer: the eye at the focal point, Reset Camera ") +
      (reset ? "on" : "off");
    vox->SetResetCamera(reset);
    vox->SetCameraPosition(1.5, 1.5, 1.5);
    vox->Update();
    Warned(1, "The camera is degenerate", what);
    double range[2];
    vox->GetOutput()->GetPointData()->GetArray("SpanCount")->GetRange(range);
    Check(range[1] == 0 && FiniteEverywhere(vox->GetOutput(), "Thickness") &&
        FiniteEverywhere(vox->GetOutput(), "DepthToDistance"),
      what + ": no spans, finite Thickness and DepthToDistance");
    vox->SetCameraPosition(1.5, 2, 12);
  }
}

void BoundaryParticles()
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Spheres of radius 1.04 at spacing 1 cover their cells (of 2.08): the inner ones are
  // culled.
  auto clean = Block(12, 1.04);
  vtkNew<vtkSPHBoundaryParticles> filter;
  Observe(filter);
  filter->SetRadius(1.04);
  RadiusCases(filter.Get(), clean, 1.04, "boundary particles");
  filter->Update();
  Check(filter->GetOutput()->GetNumberOfPoints() < 1728, "boundary particles: some are culled");
  vtkSPHBoundaryParticles* f = filter;
  PropertyCases(f,
    { { "Radius", [&](double x) { f->SetRadiusArrayName(nullptr), f->SetRadius(x); }, 1.04, nan, 0, "" },
      { "RadiusScale", [&](double x) { f->SetRadiusScale(x); }, 1, nan, 0, "" },
      { "CellSize", [&](double x) { f->SetCellSize(x); }, 0, nan, 0, "" },
      { "CellSize", [&](double x) { f->SetCellSize(x); }, 0, -1, 0, "CellSize -1 is outside" },
      { "Radius", [&](double x) { f->SetRadius(x); }, 1.04, 1e300, 1e15,
        "Radius 1e+300 is outside [0, 1e+15]: clamped to 1e+15" } },
    "boundary particles");
}
}

int main()
{
  Voxelizer();
  BoundaryParticles();
  std::printf("%s\n", Failures == 0 ? "PASSED" : "FAILED");
  return Failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
