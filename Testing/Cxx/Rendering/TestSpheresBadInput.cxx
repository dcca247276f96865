// vtkCGTSphereMapper on bad input. Each case gives exactly the warnings it names (counted,
// and each naming its problem), renders exactly the picture of the scene without the bad
// part (tolerance 0), and leaves a float frame without NaN, infinite or out-of-range values
// (vtkRayMapperStatistics::ValidateFrames) after every render that draws:
//   - an empty input; points with NaN / infinite coordinates; radii that are zero,
//     negative, NaN, infinite or huge (1e20, 1e300); a missing radius array;
//   - integer radius and colour arrays (no warning, the picture of the float arrays);
//     a 3-component radius array (one warning, its first component used; equal
//     components: no warning);
//   - a NaN colour scalar: the lookup table's NaN colour, the sphere drawn;
//   - opacity arrays: NaN values (one warning, those spheres hidden: the picture of
//     opacity 0 there), a missing array, a string array, a component beyond the array's
//     (one warning each, the picture without the array or of component 0);
//   - NaN, negative and huge property values (one warning each; NaN keeps the value, the
//     others are clamped: the picture of the bound set directly);
//   - degenerate cameras: a zero view angle (VTK clamps it; drawn, no warning), the eye at
//     the focal point and a NaN position (one warning each, nothing drawn, the background).
#include "BadInputViewer.h"
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"

#include "vtkActor.h"
#include "vtkIntArray.h"
#include "vtkLookupTable.h"
#include "vtkProperty.h"
#include "vtkStringArray.h"

#include <functional>
#include <limits>

namespace
{
using raymappers::test::RGBImage;

struct Viewer : rmtest::BadInputViewer<vtkCGTSphereMapper, vtkPolyData>
{
  vtkNew<vtkActor> Actor;
  Viewer()
  {
    Mapper->SetScalarRange(0, 30);
    Actor->SetMapper(Mapper);
    Ren->AddActor(Actor);
    Ren->GetActiveCamera()->SetViewAngle(40);
    Ren->SetNearClippingPlaneTolerance(1e-4);
    Open(160, 0.5, 0.7, 6);
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
  return rmtest::MakeSpheres(c, r);
}

// A copy of the lattice's radius array as `name` with 3 components: (r, second(r), r).
void AddRadius3(vtkPolyData* data, const char* name, const std::function<double(double)>& second)
{
  vtkDataArray* r = data->GetPointData()->GetArray("radius");
  vtkNew<vtkDoubleArray> r3;
  r3->SetName(name);
  r3->SetNumberOfComponents(3);
  for (vtkIdType i = 0; i < r->GetNumberOfTuples(); ++i)
  {
    const double v = r->GetComponent(i, 0);
    r3->InsertNextTuple3(v, second(v), v);
  }
  data->GetPointData()->AddArray(r3);
}

void BadData(Viewer& reference, const RGBImage& expected, vtkPolyData* clean)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto& log = reference.Log;
  {
    Viewer v;
    vtkNew<vtkPolyData> empty;
    const RGBImage img = v.Show(empty);
    v.Log.Warned(1, "no points", "empty input");
    v.Log.Check(rmtest::AllPixels(img, 0, 0, 0), "empty input: the background only");
    log.Ok = log.Ok && v.Log.Ok;
  }
  auto data = WithExtraPoints(
    clean, { { nan, 0, 0 }, { 0, inf, 0 }, { nan, nan, nan } }, { 0.3, 0.3, 0.3 });
  log.SameImage(reference.Show(data), expected, "NaN and infinite coordinates");
  log.Warned(1, "NaN or infinite coordinates", "NaN and infinite coordinates");
  log.ValidFrame("NaN and infinite coordinates");
  log.Check(reference.Mapper->GetStatistics()->GetCounter("spheres") == 27, "27 spheres drawn");

  data = WithExtraPoints(clean,
    { { 0.5, 0.5, 0.5 }, { -0.5, 0.5, 0 }, { 0, 0, 0.5 }, { 0.2, 0.1, 0 }, { 0, 0.1, 0.2 },
      { 0.1, 0, 0.1 } },
    { 0.0, -0.2, nan, inf, 1e20, 1e300 });
  log.SameImage(reference.Show(data), expected, "zero, negative, NaN, infinite and huge radii");
  log.Warned(1, "6 spheres have a zero, negative, non-finite or huge", "bad radii");
  log.ValidFrame("bad radii");
  // VTK's Reset Camera frames the finite points and the drawn radii only (infinite
  // coordinates and skipped radii of 1e300 must not make the bounds infinite or huge).
  reference.Show(clean);
  const RGBImage framed = rmtest::ResetCameraImage(reference.Ren, reference.Win);
  reference.Mapper->SetInputData(WithExtraPoints(clean,
    { { 0, std::numeric_limits<double>::infinity(), 0 }, { 0.1, 0, 0.1 } }, { 0.3, 1e300 }));
  log.SameImage(rmtest::ResetCameraImage(reference.Ren, reference.Win), framed,
    "Reset Camera with an infinite coordinate and a radius of 1e300");
  log.Warned(2, "are not drawn", "Reset Camera with bad points");
  log.ValidFrame("Reset Camera with bad points");
  reference.Show(clean);
  log.Silent("the clean lattice again");
}

void ArrayKinds(Viewer& reference, const RGBImage& expected, vtkPolyData* clean)
{
  auto& log = reference.Log;
  // A radius array that does not exist: the constant radius.
  {
    Viewer constant;
    constant.Mapper->SetRadius(0.2);
    const RGBImage withConstant = constant.Show(clean);
    reference.Mapper->SetRadius(0.2);
    reference.Mapper->SetRadiusArrayName("no_such_array");
    log.SameImage(reference.Show(clean), withConstant, "missing radius array");
    log.Warned(1, "'no_such_array' is not a point array of the input; using the constant radius 0.2.",
      "missing radius array");
    log.ValidFrame("missing radius array");
    reference.Mapper->SetRadius(1.0);
  }
  // Integer arrays (radius in tenths would not be integers: radii 1 and 2 at spacing 6,
  // colours 0..26) draw what the same values in double arrays draw, silently.
  {
    std::vector<std::array<double, 3>> c;
    std::vector<double> r;
    for (int i = 0; i < 27; ++i)
    {
      c.push_back({ 6.0 * (i % 3) - 6, 6.0 * ((i / 3) % 3) - 6, 6.0 * (i / 9) - 6 });
      r.push_back(1 + i % 2);
    }
    auto grid = rmtest::MakeSpheres(c, r);
    vtkNew<vtkIntArray> ir, iv;
    ir->SetName("iradius");
    iv->SetName("ivalue");
    for (int i = 0; i < 27; ++i)
    {
      ir->InsertNextValue(1 + i % 2);
      iv->InsertNextValue(i);
    }
    grid->GetPointData()->AddArray(ir);
    grid->GetPointData()->AddArray(iv);
    Viewer floats, ints;
    for (Viewer* w : { &floats, &ints })
    {
      w->Ren->GetActiveCamera()->SetPosition(3, 4, 40);
      w->Mapper->SetScalarModeToUsePointFieldData();
    }
    floats.Mapper->SetRadiusArrayName("radius");
    floats.Mapper->SelectColorArray("value");
    ints.Mapper->SetRadiusArrayName("iradius");
    ints.Mapper->SelectColorArray("ivalue");
    const RGBImage a = floats.Show(grid);
    const RGBImage b = ints.Show(grid);
    ints.Log.SameImage(b, a, "integer radius and colour arrays");
    ints.Log.Silent("integer arrays");
    ints.Log.ValidFrame("integer arrays");
    log.Ok = log.Ok && ints.Log.Ok && floats.Log.Ok;
  }
  // A 3-component radius: its first component, one warning naming it; equal components
  // (vtkPDBReader's radius) read the same and say nothing.
  {
    auto three = vtkSmartPointer<vtkPolyData>::New();
    three->DeepCopy(clean);
    AddRadius3(three, "radius3", [](double v) { return 3 * v; });
    AddRadius3(three, "radiusxyz", [](double v) { return v; });
    reference.Mapper->SetRadiusArrayName("radius3");
    log.SameImage(reference.Show(three), expected, "3-component radius");
    log.Warned(1, "radius array 'radius3' has 3 components that differ: the first is used",
      "3-component radius");
    reference.Render();
    log.Silent("3-component radius, rendered again");
    reference.Mapper->SetRadiusArrayName("radiusxyz");
    log.SameImage(reference.Show(three), expected, "3 equal components");
    log.Silent("3 equal components");
    reference.Mapper->SetRadiusArrayName("radius");
    reference.Show(clean);
  }
}

// A NaN colour scalar is coloured with the lookup table's NaN colour (vtkScalarsToColors, as
// every VTK mapper colours it), and the sphere is drawn.
void NaNColour(Viewer& reference, vtkPolyData* clean)
{
  auto& log = reference.Log;
  vtkNew<vtkLookupTable> lut;
  lut->SetTableRange(0, 30);
  lut->Build();
  double first[4];
  lut->GetTableValue(0, first);
  lut->SetNanColor(first);
  reference.Mapper->SetLookupTable(lut);
  reference.Mapper->UseLookupTableScalarRangeOn();
  auto withZero = vtkSmartPointer<vtkPolyData>::New();
  withZero->DeepCopy(clean);
  withZero->GetPointData()->GetArray("value")->SetComponent(13, 0, 0.0);
  const RGBImage zero = reference.Show(withZero);
  auto withNaN = vtkSmartPointer<vtkPolyData>::New();
  withNaN->DeepCopy(clean);
  withNaN->GetPointData()->GetArray("value")->SetComponent(
    13, 0, std::numeric_limits<double>::quiet_NaN());
  const RGBImage nanPicture = reference.Show(withNaN);
  log.SameImage(nanPicture, zero, "a NaN colour scalar with the NaN colour of value 0's colour");
  log.Check(reference.Mapper->GetStatistics()->GetCounter("spheres") == 27,
    "the sphere of the NaN scalar is drawn");
  log.ValidFrame("NaN colour scalar");
  lut->SetNanColor(1, 0, 1, 1);
  const RGBImage magenta = reference.Show(withNaN);
  const auto d = raymappers::test::compareImages(magenta, zero, 0);
  log.Check(d.maxError > 100, "another NaN colour changes that sphere's colour");
  log.Silent("NaN colour scalar");
  reference.Mapper->SetLookupTable(nullptr);
  reference.Mapper->UseLookupTableScalarRangeOff();
  reference.Show(clean);
}

// A copy of the lattice with the opacity array "alpha" (0.5, `odd` at sphere 13) and a
// string array "names".
vtkSmartPointer<vtkPolyData> WithOpacities(vtkPolyData* clean, double odd)
{
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->DeepCopy(clean);
  vtkNew<vtkDoubleArray> alpha;
  alpha->SetName("alpha");
  vtkNew<vtkStringArray> names;
  names->SetName("names");
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
  {
    alpha->InsertNextValue(i == 13 ? odd : 0.5);
    names->InsertNextValue("sphere");
  }
  data->GetPointData()->AddArray(alpha);
  data->GetPointData()->AddArray(names);
  return data;
}

// Bad opacity arrays: the rest drawn, one warning each, no NaN in the frame.
void Opacities(Viewer& reference, const RGBImage& expected, vtkPolyData* clean)
{
  auto& log = reference.Log;
  vtkCGTSphereMapper* m = reference.Mapper;
  const auto zero = WithOpacities(clean, 0.0);
  m->SetOpacityArray("alpha");
  const RGBImage hidden = reference.Show(zero);
  log.Silent("an opacity array");
  log.ValidFrame("an opacity array");
  log.Check(raymappers::test::compareImages(hidden, expected, 0).maxError > 10,
    "an opacity array changes the picture");
  log.SameImage(reference.Show(WithOpacities(clean, std::numeric_limits<double>::quiet_NaN())),
    hidden, "a NaN opacity: that sphere hidden");
  log.Warned(1, "1 values of the opacity array 'alpha' are NaN", "NaN opacity");
  log.ValidFrame("NaN opacity");
  m->SetOpacityArrayComponent(2);
  log.SameImage(reference.Show(zero), hidden, "OpacityArrayComponent beyond the array");
  log.Warned(1, "OpacityArrayComponent 2 is beyond the 1 components", "component beyond");
  m->SetOpacityArrayComponent(0);
  m->SetOpacityArray("no_such_array");
  log.SameImage(reference.Show(zero), expected, "missing opacity array");
  log.Warned(1, "opacity array 'no_such_array' is not a point array of the input", "missing");
  log.ValidFrame("missing opacity array");
  m->SetOpacityArray("names");
  log.SameImage(reference.Show(zero), expected, "string opacity array");
  log.Warned(1, "opacity array 'names' is a vtkStringArray, not a numeric array", "string array");
  reference.Render();
  log.Silent("string opacity array, rendered again");
  m->SetOpacityArray(nullptr);
  log.SameImage(reference.Show(clean), expected, "no opacity array");
  log.Silent("no opacity array");
}

// NaN: one warning, the property keeps its value, the same picture. Out of range: one
// warning, clamped: the picture of the bound set directly.
void Properties(Viewer& v, const RGBImage& expected)
{
  auto& log = v.Log;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  vtkCGTSphereMapper* m = v.Mapper;
  const auto render = [&] { return v.Render(); };
  auto shadows = [&] {
    m->SetShadowRays(2);
    m->AutomaticShadowLightOff();
    m->SetShadowLightPosition(3, 4, 5);
    m->SetShadowLightSize(0.5);
  };
  auto noShadows = [&] {
    m->SetShadowRays(0);
    m->AutomaticShadowLightOn();
  };
  auto nothing = [] {};
  rmtest::CheckNaNCases(log, render,
    { { "Radius", [&] { m->SetRadiusArrayName(nullptr), m->SetRadius(0.2); },
        [&] { m->SetRadius(nan); }, [&] { m->SetRadiusArrayName("radius"), m->SetRadius(1); } },
      { "RadiusScale", nothing, [&] { m->SetRadiusScale(nan); }, nothing },
      { "Lambda", nothing, [&] { m->SetLambda(nan); }, nothing },
      { "AmbientOcclusionRadius",
        [&] { m->SetAmbientOcclusionSamples(4), m->SetAmbientOcclusionRadius(0.3); },
        [&] { m->SetAmbientOcclusionRadius(nan); },
        [&] { m->SetAmbientOcclusionSamples(0), m->SetAmbientOcclusionRadius(0); } },
      { "ShadowLightSize", shadows, [&] { m->SetShadowLightSize(nan); }, noShadows },
      { "ShadowLightIntensity", shadows, [&] { m->SetShadowLightIntensity(nan); }, noShadows },
      { "ShadowLightPosition", shadows, [&] { m->SetShadowLightPosition(nan, 0, 0); },
        noShadows },
      { "range 0", [&] { m->SetRange(0, "value", 5, 20); },
        [&] { m->SetRange(0, "value", nan, 10); }, [&] { m->RemoveAllRanges(); } } });
  // Infinity is rejected as NaN is (clamped, it would become the largest value).
  const RGBImage before = v.Render();
  m->SetRadiusScale(std::numeric_limits<double>::infinity());
  log.Warned(1, "RadiusScale inf is not finite: ignored; RadiusScale stays 1", "RadiusScale inf");
  log.SameImage(v.Render(), before, "RadiusScale inf: the picture before it");
  // Clamped values that do not change the picture (the tiles, packets and grid resolution
  // do not): the clean picture.
  m->SetTileSize(1000000);
  log.Warned(1, "TileSize 1000000 is outside [4, 256]: clamped to 256", "TileSize huge");
  m->SetPacketSize(-3);
  log.Warned(1, "PacketSize -3 is outside [1, 16]: clamped to 1", "PacketSize negative");
  log.SameImage(v.Render(), expected, "TileSize and PacketSize clamped");
  log.ValidFrame("TileSize and PacketSize clamped");
  m->SetTileSize(32);
  m->SetPacketSize(8);
  // Clamped values that do: the picture of the bound.
  rmtest::CheckClampCases(log,
    render,
    { { "Lambda",
        [&](double x) { m->SetLambda(x); },
        -5,
        0.01,
        "Lambda -5 is outside [0.01, 100]: clamped to 0.01" },
      { "RadiusScale",
        [&](double x) { m->SetRadiusScale(x); },
        -1,
        0,
        "RadiusScale -1 is outside [0, 1e+15]: clamped to 0",
        1,
        "27 spheres have a zero, negative, non-finite or huge" },
      { "RadiusScale",
        [&](double x) { m->SetRadiusScale(x); },
        1e300,
        1e15,
        "RadiusScale 1e+300 is outside [0, 1e+15]: clamped to 1e+15" },
      { "AmbientOcclusionRadius",
        [&](double x) { m->SetAmbientOcclusionSamples(4), m->SetAmbientOcclusionRadius(x); },
        1e300,
        1e15,
        "AmbientOcclusionRadius 1e+300 is outside" },
      { "ShadowLightIntensity",
        [&](double x)
        { m->SetShadowRays(2), m->AutomaticShadowLightOff(), m->SetShadowLightIntensity(x); },
        1e300,
        1e15,
        "ShadowLightIntensity 1e+300 is outside" },
      { "ShadowLightPosition",
        [&](double x) { m->SetShadowLightPosition(x, 3, 5); },
        -1e300,
        -1e15,
        "ShadowLightPosition has components outside" },
      { "AmbientOcclusionSamplesPerFrame",
        [&](double x)
        { m->SetAmbientOcclusionSamples(4), m->SetAmbientOcclusionSamplesPerFrame(int(x)); },
        -3,
        0,
        "AmbientOcclusionSamplesPerFrame -3 is outside [0, 256]: clamped to 0" },
      { "AmbientOcclusionSamplesPerFrame",
        [&](double x)
        { m->SetAmbientOcclusionSamples(4), m->SetAmbientOcclusionSamplesPerFrame(int(x)); },
        2e9,
        256,
        "AmbientOcclusionSamplesPerFrame 2000000000 is outside [0, 256]: clamped to 256" } });
  m->SetAmbientOcclusionSamplesPerFrame(0);
  m->SetLambda(1);
  m->SetRadiusScale(1);
  m->SetAmbientOcclusionSamples(0);
  m->SetShadowRays(0);
  m->AutomaticShadowLightOn();
  m->SetShadowLightIntensity(1);
  log.SameImage(v.Render(), expected, "the properties restored");
  log.Silent("the properties restored");
}
}

int TestSpheresBadInput(int, char*[])
{
  auto clean = rmtest::MakeLattice(3);
  Viewer reference;
  reference.Mapper->SetRadiusArrayName("radius");
  const RGBImage expected = reference.Show(clean);
  reference.Log.Silent("the clean lattice");
  reference.Log.ValidFrame("the clean lattice");

  BadData(reference, expected, clean);
  ArrayKinds(reference, expected, clean);
  NaNColour(reference, clean);
  Opacities(reference, expected, clean);
  Properties(reference, expected);
  rmtest::CheckDegenerateCameras(reference.Log, reference.Ren->GetActiveCamera(),
    [&] { return reference.Render(); }, expected, { 0, 0, 0 });
  return reference.Log.Ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
