// vtkRBFVolumeMapper on bad input. Each case gives exactly the warnings it names, renders
// exactly the picture of the scene without the bad part (tolerance 0) and leaves a float
// frame without NaN, infinite or out-of-range values (ValidateFrames) after every render:
//   - particles with NaN coordinates, NaN / infinite / huge (1e300, beyond float) values,
//     zero / negative / NaN / infinite / huge radii: skipped, one warning each kind;
//   - missing value, radius and field arrays: one warning each, the fallbacks drawn;
//   - an integer value array (the picture of the double one, silently); a 3-component value
//     array (one warning, its first component);
//   - an empty input (one warning, nothing drawn);
//   - NaN, negative and huge property values (one warning each; NaN keeps the value, the
//     others are clamped: the picture of the bound set directly);
//   - degenerate cameras (zero view angle drawn; the eye at the focal point and a NaN
//     position: one warning each, nothing drawn).
#include "BadInputViewer.h"
#include "RenderingTestHelpers.h"
#include "vtkRBFVolumeMapper.h"

#include "vtkColorTransferFunction.h"
#include "vtkIntArray.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <limits>

namespace
{
using raymappers::test::RGBImage;

struct Viewer : rmtest::BadInputVolumeViewer<vtkRBFVolumeMapper, vtkPolyData>
{
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
    Mapper->SetKappa(1); // the pictures' kappa (the automatic one is restored to 1 below)
    Ren->GetActiveCamera()->SetViewAngle(40);
    ClipHalfSide = 3;
    Open(120, 0.5, 0.7, 6);
  }
};

// The lattice with particles added that must all be skipped: NaN coordinates, bad radii,
// bad values (the "value" array holds each point's index; the added ones get bad values).
vtkSmartPointer<vtkPolyData> Dirty(vtkPolyData* clean)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<std::array<double, 3>> c;
  std::vector<double> r;
  for (vtkIdType i = 0; i < clean->GetNumberOfPoints(); ++i)
  {
    std::array<double, 3> p;
    clean->GetPoint(i, p.data());
    c.push_back(p);
    r.push_back(clean->GetPointData()->GetArray("radius")->GetComponent(i, 0));
  }
  c.push_back({ nan, 0, 0 });
  r.push_back(0.2);
  c.push_back({ 0, inf, 0 });
  r.push_back(0.2);
  for (const double bad : { 0.0, -0.3, nan, inf, 1e20, 1e300 })
  {
    c.push_back({ 0.1, 0.2, 0.3 });
    r.push_back(bad);
  }
  const std::size_t valued = c.size();
  for (int k = 0; k < 3; ++k)
  {
    c.push_back({ 0.3, 0.1 * k, 0.0 });
    r.push_back(0.2);
  }
  auto dirty = rmtest::MakeSpheres(c, r);
  vtkDataArray* values = dirty->GetPointData()->GetArray("value");
  values->SetComponent(valued, 0, nan);
  values->SetComponent(valued + 1, 0, inf);
  values->SetComponent(valued + 2, 0, 1e300); // finite as double, infinite as float
  return dirty;
}

vtkSmartPointer<vtkPolyData> WithArrayKinds(vtkPolyData* clean)
{
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->DeepCopy(clean);
  vtkDataArray* values = data->GetPointData()->GetArray("value");
  vtkNew<vtkIntArray> ints;
  ints->SetName("ivalue");
  vtkNew<vtkDoubleArray> three;
  three->SetName("value3");
  three->SetNumberOfComponents(3);
  for (vtkIdType i = 0; i < values->GetNumberOfTuples(); ++i)
  {
    const double v = values->GetComponent(i, 0);
    ints->InsertNextValue(static_cast<int>(v));
    three->InsertNextTuple3(v, -v, 2 * v);
  }
  data->GetPointData()->AddArray(ints);
  data->GetPointData()->AddArray(three);
  return data;
}

void Data(Viewer& v, vtkPolyData* clean, const RGBImage& reference)
{
  rmtest::BadInputLog& log = v.Log;
  v.Mapper->SetValueArrayName("value");
  const RGBImage valued = v.Show(clean);
  log.Silent("the valued lattice");
  log.SameImage(v.Show(Dirty(clean)), valued, "bad particles");
  log.Warned(2, "are not drawn", "bad particles (coordinates or values; radii)");
  log.ValidFrame("bad particles");
  log.Check(v.Mapper->GetStatistics()->GetCounter("particles") == clean->GetNumberOfPoints(),
    "only the lattice's particles are drawn");
  // VTK's Reset Camera frames the finite points and the drawn radii only.
  v.Mapper->SetInputData(clean);
  const RGBImage framed = rmtest::ResetCameraImage(v.Ren, v.Win);
  v.Mapper->SetInputData(Dirty(clean));
  log.SameImage(rmtest::ResetCameraImage(v.Ren, v.Win), framed,
    "Reset Camera with infinite coordinates and radii of 1e20 and 1e300");
  log.Warned(2, "are not drawn", "Reset Camera with bad particles");
  log.ValidFrame("Reset Camera with bad particles");

  auto kinds = WithArrayKinds(clean);
  v.Mapper->SetValueArrayName("ivalue");
  log.SameImage(v.Show(kinds), valued, "an integer value array");
  log.Silent("an integer value array");
  log.ValidFrame("an integer value array");
  v.Mapper->SetValueArrayName("value3");
  log.SameImage(v.Render(), valued, "a 3-component value array");
  log.Warned(1, "value array 'value3' has 3 components that differ: the first is used",
    "a 3-component value array");
  v.Render();
  log.Silent("a 3-component value array, rendered again");
  v.Mapper->SetValueArrayName(nullptr);

  v.Mapper->SetRadiusArrayName("no-such-radius");
  v.Mapper->SetValueArrayName("no-such-value");
  v.Mapper->SetFieldArrayName("no-such-field");
  v.Show(clean);
  log.Warned(3, "is not a point array of the input", "missing radius, value and field arrays");
  log.ValidFrame("missing arrays");
  v.Mapper->SetRadiusArrayName("radius");
  v.Mapper->SetValueArrayName(nullptr);
  v.Mapper->SetFieldArrayName(nullptr);
  log.SameImage(v.Show(clean), reference, "the arrays restored");
  log.Silent("the arrays restored");

  vtkNew<vtkPolyData> empty;
  log.Check(rmtest::AllPixels(v.Show(empty), 0, 0, 0), "empty input: nothing drawn");
  log.Warned(1, "no points", "empty input");
  v.Show(clean);
}

void Properties(Viewer& v)
{
  rmtest::BadInputLog& log = v.Log;
  vtkRBFVolumeMapper* m = v.Mapper;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto render = [&] { return v.Render(); };
  auto nothing = [] {};
  rmtest::CheckNaNCases(log, render,
    { { "Kappa", nothing, [&] { m->SetKappa(nan); }, nothing },
      { "Sigma", nothing, [&] { m->SetSigma(nan); }, nothing },
      { "SampleDistance", nothing, [&] { m->SetSampleDistance(nan); }, nothing },
      { "Radius", [&] { m->SetRadiusArrayName(nullptr), m->SetRadius(0.2); },
        [&] { m->SetRadius(nan); }, [&] { m->SetRadiusArrayName("radius"); } },
      { "RadiusScale", nothing, [&] { m->SetRadiusScale(nan); }, nothing },
      { "TerminationOpacity", nothing, [&] { m->SetTerminationOpacity(nan); }, nothing } });
  rmtest::CheckClampCases(log, render,
    { { "Sigma", [&](double x) { m->SetSigma(x); }, -5, 0, "Sigma -5 is outside [0, 1000]" },
      { "Kappa", [&](double x) { m->SetKappa(x); }, -1, 0, "Kappa -1 is outside [0, 1e+15]" },
      { "Kappa", [&](double x) { m->SetKappa(x); }, 1e300, 1e15, "Kappa 1e+300 is outside" },
      { "SamplesPerPass", [&](double x) { m->SetSamplesPerPass(static_cast<int>(x)); }, 100000,
        256, "SamplesPerPass 100000 is outside [1, 256]" },
      { "TerminationOpacity", [&](double x) { m->SetTerminationOpacity(x); }, 7, 1,
        "TerminationOpacity 7 is outside [0, 1]" },
      { "RadiusScale", [&](double x) { m->SetRadiusScale(x); }, 1e300, 1e15,
        "RadiusScale 1e+300 is outside" },
      { "SampleDistance", [&](double x) { m->SetSampleDistance(x); }, 1e300, 1e15,
        "SampleDistance 1e+300 is outside" } });
  m->SetSigma(3);
  m->SetKappa(1);
  m->SetSamplesPerPass(32);
  m->SetTerminationOpacity(0.99);
  m->SetRadiusScale(2);
  m->SetSampleDistance(0.05);
  v.Render();
  log.Silent("the properties restored");
}
}

int TestRBFBadInput(int, char*[])
{
  auto clean = rmtest::MakeLattice(4);
  Viewer v;
  v.Mapper->SetRadiusArrayName("radius");
  v.Mapper->SetRadiusScale(2.0);
  const RGBImage reference = v.Show(clean);
  v.Log.Silent("the lattice");
  v.Log.ValidFrame("the lattice");
  Data(v, clean, reference);
  Properties(v);
  v.Log.SameImage(v.Render(), reference, "everything restored");
  rmtest::CheckDegenerateCameras(v.Log, v.Ren->GetActiveCamera(), [&] { return v.Render(); },
    reference, { 0, 0, 0 });
  return v.Log.Ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
