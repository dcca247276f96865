// vtkSPHVolumeMapper on bad input. Each case gives exactly the warnings it names, renders
// exactly the picture of the scene without the bad part (tolerance 0) and leaves a float
// frame without NaN, infinite or out-of-range values (ValidateFrames) after every render:
//   - missing smoothing length, mass and density arrays (the constants, the same picture);
//   - particles with NaN / infinite positions, zero / negative / NaN / infinite / huge
//     smoothing lengths, a zero density (infinite volume), a NaN mass, NaN / infinite /
//     beyond-float quantities: skipped (one warning each kind), the picture of the others;
//   - integer quantity and smoothing-length arrays (the picture of the double ones,
//     silently); a 3-component smoothing length (one warning, its first component);
//   - NaN, negative and huge property values (one warning each; NaN keeps the value, the
//     others are clamped: the picture of the bound set directly);
//   - degenerate cameras (zero view angle drawn; the eye at the focal point and a NaN
//     position: one warning each, nothing drawn); a camera inside the particles;
//   - an empty input (one warning, nothing drawn).
#include "BadInputViewer.h"
#include "RenderingTestHelpers.h"
#include "vtkSPHVolumeMapper.h"

#include "vtkColorTransferFunction.h"
#include "vtkIntArray.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <limits>

namespace
{
using raymappers::test::RGBImage;

struct Viewer : rmtest::BadInputVolumeViewer<vtkSPHVolumeMapper, vtkPolyData>
{
  Viewer()
  {
    vtkNew<vtkColorTransferFunction> color;
    color->AddRGBPoint(0, 0.2, 0.4, 1.0);
    color->AddRGBPoint(215, 1.0, 0.3, 0.2);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(0, 0.3);
    opacity->AddPoint(215, 0.8);
    Property->SetColor(color);
    Property->SetScalarOpacity(opacity);
    Mapper->SetSmoothingLength(0.2);
    Mapper->SetValueArrayName("value");
    Open(96, 1, 2, 7);
  }
};

void AddConstant(vtkPolyData* data, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfTuples(data->GetNumberOfPoints());
  a->Fill(value);
  data->GetPointData()->AddArray(a);
}

// The 6^3 lattice with h, m and rho arrays (0.2, 1, 1), and a copy with particles appended
// that are all bad (inside the lattice's bounds, so the origin of the float coordinates
// stays the same).
vtkSmartPointer<vtkPolyData> Lattice()
{
  auto lattice = rmtest::MakeLattice(6);
  AddConstant(lattice, "h", 0.2);
  AddConstant(lattice, "m", 1.0);
  AddConstant(lattice, "rho", 1.0);
  return lattice;
}

vtkSmartPointer<vtkPolyData> WithBadParticles(vtkPolyData* clean)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Bad
  {
    double x, y, z, h, m, rho, q;
  };
  // 2 non-finite positions; 5 bad smoothing lengths; a zero density, a NaN mass and NaN,
  // infinite and 1e300 quantities (5 non-finite "coordinates, quantities or volumes").
  const std::vector<Bad> bad = { { nan, 0, 0, 0.2, 1, 1, 1 }, { 0, inf, 0, 0.2, 1, 1, 1 },
    { 0.1, 0.1, 0.1, 0.0, 1, 1, 1 }, { 0.1, 0.1, 0.1, -0.2, 1, 1, 1 },
    { 0.1, 0.1, 0.1, nan, 1, 1, 1 }, { 0.1, 0.1, 0.1, inf, 1, 1, 1 },
    { 0.1, 0.1, 0.1, 1e20, 1, 1, 1 }, { 0.2, 0.1, 0.1, 0.2, 1, 0, 1 },
    { 0.2, 0.1, 0.1, 0.2, nan, 1, 1 }, { 0.2, 0.2, 0.1, 0.2, 1, 1, nan },
    { 0.2, 0.2, 0.1, 0.2, 1, 1, inf }, { 0.2, 0.2, 0.1, 0.2, 1, 1, 1e300 } };
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(clean);
  vtkPointData* pd = out->GetPointData();
  for (const Bad& b : bad)
  {
    out->GetPoints()->InsertNextPoint(b.x, b.y, b.z);
    pd->GetArray("radius")->InsertNextTuple1(0.1);
    pd->GetArray("value")->InsertNextTuple1(b.q);
    pd->GetArray("h")->InsertNextTuple1(b.h);
    pd->GetArray("m")->InsertNextTuple1(b.m);
    pd->GetArray("rho")->InsertNextTuple1(b.rho);
  }
  return out;
}

vtkSmartPointer<vtkPolyData> WithArrayKinds(vtkPolyData* clean)
{
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->DeepCopy(clean);
  vtkNew<vtkIntArray> q, h;
  q->SetName("ivalue");
  h->SetName("ih");
  vtkNew<vtkDoubleArray> h3;
  h3->SetName("h3");
  h3->SetNumberOfComponents(3);
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
  {
    q->InsertNextValue(static_cast<int>(i));
    h->InsertNextValue(1);
    h3->InsertNextTuple3(0.2, 0.5, 0.0);
  }
  data->GetPointData()->AddArray(q);
  data->GetPointData()->AddArray(h);
  data->GetPointData()->AddArray(h3);
  return data;
}

void Data(Viewer& v, vtkPolyData* clean, const RGBImage& good)
{
  rmtest::BadInputLog& log = v.Log;
  vtkSPHVolumeMapper* m = v.Mapper;
  m->SetSmoothingLengthArrayName("no-such-h");
  m->SetMassArrayName("no-such-mass");
  m->SetDensityArrayName("no-such-rho");
  log.SameImage(v.Render(), good, "missing h, mass and density arrays: the constants");
  log.Warned(2, "is not a point array", "missing h and mass/density arrays");
  log.ValidFrame("missing arrays");

  m->SetSmoothingLengthArrayName("h");
  m->SetMassArrayName("m");
  m->SetDensityArrayName("rho");
  log.SameImage(v.Render(), good, "the h, m and rho arrays of the constants");
  log.Silent("h, m and rho arrays");
  log.SameImage(v.Show(WithBadParticles(clean)), good, "bad particles appended");
  log.Warned(2, "particles have", "bad particles (positions, quantities or volumes; h)");
  log.ValidFrame("bad particles");
  log.Check(m->GetStatistics()->GetCounter("particles") == 216, "216 particles drawn");
  // VTK's Reset Camera frames the finite points and the drawn supports only.
  m->SetInputData(clean);
  const RGBImage framed = rmtest::ResetCameraImage(v.Ren, v.Win);
  m->SetInputData(WithBadParticles(clean));
  log.SameImage(rmtest::ResetCameraImage(v.Ren, v.Win), framed,
    "Reset Camera with an infinite position and a smoothing length of 1e20");
  log.Warned(2, "particles have", "Reset Camera with bad particles");
  log.ValidFrame("Reset Camera with bad particles");

  auto kinds = WithArrayKinds(clean);
  m->SetValueArrayName("ivalue");
  m->SetSmoothingLengthArrayName("ih");
  m->SetSmoothingLengthScale(0.2);
  log.SameImage(v.Show(kinds), good, "integer quantity and smoothing length arrays");
  log.Silent("integer arrays");
  log.ValidFrame("integer arrays");
  m->SetValueArrayName("value");
  m->SetSmoothingLengthScale(1);
  m->SetSmoothingLengthArrayName("h3");
  log.SameImage(v.Render(), good, "a 3-component smoothing length");
  log.Warned(1, "smoothing length array 'h3' has 3 components that differ: the first is used",
    "a 3-component smoothing length");
  m->SetSmoothingLengthArrayName(nullptr);
  m->SetMassArrayName(nullptr);
  m->SetDensityArrayName(nullptr);
  log.SameImage(v.Show(clean), good, "the constants again");
  log.Silent("the constants again");
}

void Properties(Viewer& v)
{
  rmtest::BadInputLog& log = v.Log;
  vtkSPHVolumeMapper* m = v.Mapper;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto render = [&] { return v.Render(); };
  auto nothing = [] {};
  rmtest::CheckNaNCases(log, render,
    { { "SmoothingLength", nothing, [&] { m->SetSmoothingLength(nan); }, nothing },
      { "SmoothingLengthScale", nothing, [&] { m->SetSmoothingLengthScale(nan); }, nothing },
      { "Volume", [&] { m->SetNormalization(VTK_SPH_UNNORMALIZED); }, [&] { m->SetVolume(nan); },
        [&] { m->SetNormalization(VTK_SPH_NORMALIZED); } },
      { "SupportFactor", nothing, [&] { m->SetSupportFactor(nan); }, nothing },
      { "ReferenceWeightSum",
        [&] { m->SetNormalization(VTK_SPH_PSEUDO_NORMALIZED), m->SetReferenceWeightSum(2); },
        [&] { m->SetReferenceWeightSum(nan); },
        [&] { m->SetNormalization(VTK_SPH_NORMALIZED), m->SetReferenceWeightSum(0); } },
      { "ContourColor", [&] { m->ContourShadingOn(), m->SetContourColor(1, 0, 0); },
        [&] { m->SetContourColor(nan, 0, 0); }, [&] { m->ContourShadingOff(); } },
      { "ContourOpacity", [&] { m->ContourShadingOn(); }, [&] { m->SetContourOpacity(nan); },
        [&] { m->ContourShadingOff(); } },
      { "StepFactor", nothing, [&] { m->SetStepFactor(nan); }, nothing },
      { "SamplesPerSupport", nothing, [&] { m->SetSamplesPerSupport(nan); }, nothing },
      { "SmallestSupport", nothing, [&] { m->SetSmallestSupport(nan); }, nothing },
      { "FloatOrigin", [&] { m->UseFloatOriginOn(), m->SetFloatOrigin(0.1, 0.2, 0.3); },
        [&] { m->SetFloatOrigin(nan, 0, 0); }, [&] { m->UseFloatOriginOff(); } },
      { "TerminationOpacity", nothing, [&] { m->SetTerminationOpacity(nan); }, nothing },
      { "MaximumReduction", nothing, [&] { m->SetMaximumReduction(nan); }, nothing },
      { "FrameBudget", nothing, [&] { m->SetFrameBudget(nan); }, nothing } });
  rmtest::CheckClampCases(log, render,
    { { "SmoothingLength", [&](double x) { m->SetSmoothingLength(x); }, -1, 0,
        "SmoothingLength -1 is outside [0, 1e+15]: clamped to 0" }, // 0: automatic, drawn
      // The bound gives supports of 2e15 (the cubic spline's 2h), above the largest length.
      { "SmoothingLength", [&](double x) { m->SetSmoothingLength(x); }, 1e300, 1e15,
        "SmoothingLength 1e+300 is outside", 1,
        "216 particles have a zero, negative, non-finite or huge (above 1e15) smoothing length" },
      { "SupportFactor", [&](double x) { m->SetSmoothingLength(0.2), m->SetSupportFactor(x); },
        1e300, 100, "SupportFactor 1e+300 is outside [0, 100]" },
      { "Volume", [&](double x) { m->SetSupportFactor(0), m->SetVolume(x); }, -1, 0,
        "Volume -1 is outside [0, 1e+15]" },
      { "Volume", [&](double x) { m->SetVolume(x); }, 1e300, 1e15, "Volume 1e+300 is outside" },
      { "StepFactor", [&](double x) { m->SetVolume(1), m->SetStepFactor(x); }, 0, 0.05,
        "StepFactor 0 is outside [0.05, 64]" },
      { "TileSize", [&](double x) { m->SetStepFactor(1), m->SetTileSize(static_cast<int>(x)); },
        1000, 64, "TileSize 1000 is outside [2, 64]" },
      { "ContourColor",
        [&](double x) { m->SetTileSize(16), m->ContourShadingOn(), m->SetContourColor(x, 0.5, 0.5); },
        7, 1, "ContourColor has components outside [0, 1]" } });
  m->ContourShadingOff();
  m->SetContourColor(0, 0, 0);
  v.Render();
  log.Silent("the properties restored");
}
}

int TestSPHBadInput(int, char*[])
{
  auto clean = Lattice();
  Viewer v;
  const RGBImage good = v.Show(clean);
  v.Log.Silent("the lattice");
  v.Log.ValidFrame("the lattice");
  v.Log.Check(v.Mapper->GetStatistics()->GetCounter("particles") == 216, "216 particles");
  Data(v, clean, good);
  Properties(v);
  v.Log.SameImage(v.Render(), good, "everything restored");
  rmtest::CheckDegenerateCameras(v.Log, v.Ren->GetActiveCamera(), [&] { return v.Render(); },
    good, { 0, 0, 0 });

  // A camera inside the lattice: particles straddle the near plane.
  vtkCamera* camera = v.Ren->GetActiveCamera();
  camera->SetPosition(0.05, 0.02, 0.1);
  camera->SetFocalPoint(0.3, 0.2, -1);
  v.Ren->ResetCameraClippingRange();
  v.Win->Render();
  v.Log.Check(v.Mapper->GetStatistics()->GetCounter("particles_in_view") > 0,
    "camera inside: particles in view");
  v.Log.ValidFrame("camera inside");

  vtkNew<vtkPolyData> empty;
  v.Mapper->SetInputData(empty);
  v.Ren->ResetCamera();
  v.Win->Render();
  v.Log.Warned(1, "no points", "empty input");
  v.Log.Check(rmtest::AllPixels(raymappers::test::fromWindow(v.Win), 0, 0, 0),
    "empty input: nothing drawn");
  return v.Log.Ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
