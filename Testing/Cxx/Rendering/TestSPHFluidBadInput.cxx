// vtkSPHFluidMapper on bad input. Each case gives exactly the warnings it names, renders
// exactly the picture of the scene without the bad part (tolerance 0) and leaves a float
// frame without NaN, infinite or out-of-range values (ValidateFrames) after every render:
//   - a missing radius array (the constant radius, the same picture);
//   - particles with NaN / infinite positions and zero / negative / NaN / infinite / huge
//     radii: skipped (one warning each kind), the picture of the others;
//   - an integer radius array (the picture of the double one, silently); a 3-component
//     radius array (one warning, its first component);
//   - a memory budget too small for one voxel column (one warning, nothing drawn);
//   - NaN, negative and huge property values (one warning each; NaN keeps the value, the
//     others are clamped: the picture of the bound set directly);
//   - degenerate cameras (zero view angle drawn; the eye at the focal point and a NaN
//     position: one warning each, nothing drawn); a camera inside the fluid;
//   - an empty input (one warning, nothing drawn).
#include "BadInputViewer.h"
#include "RenderingTestHelpers.h"
#include "vtkSPHFluidMapper.h"

#include "vtkIntArray.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <limits>

namespace
{
using raymappers::test::RGBImage;

struct Viewer : rmtest::BadInputVolumeViewer<vtkSPHFluidMapper, vtkPolyData>
{
  Viewer()
  {
    Mapper->SetRadius(0.25);
    // The lengths in world units, as this test's pictures were made (the defaults are in
    // particle radii since the automatic radius; TestSPHFluidMapper covers those).
    Mapper->SetLengthUnitToWorld();
    Mapper->SetDensity(1);
    Mapper->SetSmoothingRadius(0);
    Mapper->SetAmbientOcclusionRadius(0.1);
    // A grey absorption and no highlight: the highlight is light added over the body, a
    // premultiplied colour above its alpha, which the frame validation counts as out of
    // range (the body itself never exceeds its alpha, FluidRenderer.h).
    Mapper->SetAbsorptionColor(0.5, 0.5, 0.5);
    Property->SetSpecular(0);
    Ren->SetBackground(0.2, 0.4, 0.6);
    Open(96, 1, 2, 7);
  }
};

// The 6^3 lattice with an "r" array of the constant radius 0.25, an integer "ir" of 1 (for
// RadiusScale 0.25) and a 3-component "r3" (0.25, 0.5, 0).
vtkSmartPointer<vtkPolyData> Lattice()
{
  auto lattice = rmtest::MakeLattice(6);
  vtkNew<vtkDoubleArray> r, r3;
  vtkNew<vtkIntArray> ir;
  r->SetName("r");
  ir->SetName("ir");
  r3->SetName("r3");
  r3->SetNumberOfComponents(3);
  for (vtkIdType i = 0; i < lattice->GetNumberOfPoints(); ++i)
  {
    r->InsertNextValue(0.25);
    ir->InsertNextValue(1);
    r3->InsertNextTuple3(0.25, 0.5, 0.0);
  }
  lattice->GetPointData()->AddArray(r);
  lattice->GetPointData()->AddArray(ir);
  lattice->GetPointData()->AddArray(r3);
  return lattice;
}

// Bad particles appended inside the lattice's bounds: 2 non-finite positions, 6 bad radii.
vtkSmartPointer<vtkPolyData> WithBadParticles(vtkPolyData* clean)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(clean);
  vtkPointData* pd = out->GetPointData();
  auto add = [&](double x, double y, double z, double r) {
    out->GetPoints()->InsertNextPoint(x, y, z);
    pd->GetArray("radius")->InsertNextTuple1(0.1);
    pd->GetArray("value")->InsertNextTuple1(0);
    pd->GetArray("r")->InsertNextTuple1(r);
    pd->GetArray("ir")->InsertNextTuple1(1);
    pd->GetArray("r3")->InsertNextTuple3(r, r, r);
  };
  add(nan, 0, 0, 0.25);
  add(0, inf, 0, 0.25);
  for (const double r : { 0.0, -0.2, nan, inf, 1e20, 1e300 })
  {
    add(0.9, 0.9, 0.9, r);
  }
  return out;
}

void Data(Viewer& v, vtkPolyData* clean, const RGBImage& good)
{
  rmtest::BadInputLog& log = v.Log;
  vtkSPHFluidMapper* m = v.Mapper;
  m->SetRadiusArrayName("no-such-radius");
  log.SameImage(v.Render(), good, "a missing radius array: the constant");
  v.Render();
  log.Warned(1, "radius array 'no-such-radius' is not a point array", "missing radius array");
  log.ValidFrame("missing radius array");

  m->SetRadiusArrayName("r");
  log.SameImage(v.Show(WithBadParticles(clean)), good, "bad particles appended");
  log.Warned(2, "particles have", "bad particles (positions; radii)");
  log.ValidFrame("bad particles");
  v.Render();
  log.Silent("bad particles, rendered again");
  log.Check(m->GetStatistics()->GetCounter("particles") == 216 &&
      m->GetStatistics()->GetCounter("particles_skipped") == 8,
    "216 particles drawn, 8 skipped");
  // VTK's Reset Camera frames the finite points and the drawn radii only.
  m->SetInputData(clean);
  const RGBImage framed = rmtest::ResetCameraImage(v.Ren, v.Win);
  m->SetInputData(WithBadParticles(clean));
  log.SameImage(rmtest::ResetCameraImage(v.Ren, v.Win), framed,
    "Reset Camera with an infinite position and radii of 1e20 and 1e300");
  log.Warned(2, "particles have", "Reset Camera with bad particles");
  log.ValidFrame("Reset Camera with bad particles");

  m->SetRadiusArrayName("ir");
  m->SetRadiusScale(0.25);
  log.SameImage(v.Show(clean), good, "an integer radius array");
  log.Silent("an integer radius array");
  log.ValidFrame("an integer radius array");
  m->SetRadiusScale(1);
  m->SetRadiusArrayName("r3");
  log.SameImage(v.Render(), good, "a 3-component radius array");
  log.Warned(1, "radius array 'r3' has 3 components that differ: the first is used",
    "a 3-component radius array");
  m->SetRadiusArrayName(nullptr);

  m->SetMemoryBudget(0.0001);
  const RGBImage nothing = v.Render();
  v.Render();
  log.Warned(1, "layers per thread need at least", "a budget too small for one column");
  log.Check(m->GetStatistics()->GetCounter("budget_exceeded") == 1 &&
      m->GetStatistics()->GetCounter("shaded_pixels") == 0 &&
      rmtest::AllPixels(nothing, 51, 102, 153),
    "budget too small: nothing drawn");
  log.ValidFrame("budget too small");
  m->SetMemoryBudget(0);
  log.SameImage(v.Render(), good, "the automatic budget restored");
}

void Properties(Viewer& v)
{
  rmtest::BadInputLog& log = v.Log;
  vtkSPHFluidMapper* m = v.Mapper;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto render = [&] { return v.Render(); };
  auto nothing = [] {};
  rmtest::CheckNaNCases(log, render,
    { { "Radius", nothing, [&] { m->SetRadius(nan); }, nothing },
      { "RadiusScale", nothing, [&] { m->SetRadiusScale(nan); }, nothing },
      { "AngleResolution", nothing, [&] { m->SetAngleResolution(nan); }, nothing },
      { "MemoryBudget", nothing, [&] { m->SetMemoryBudget(nan); }, nothing },
      { "GapThreshold", nothing, [&] { m->SetGapThreshold(nan); }, nothing },
      { "CellSize", nothing, [&] { m->SetCellSize(nan); }, nothing },
      { "SmoothingRadius", [&] { m->SetSmoothingRadius(0.2); },
        [&] { m->SetSmoothingRadius(nan); }, [&] { m->SetSmoothingRadius(0); } },
      { "Color", nothing, [&] { m->SetColor(nan, 0.5, 0.5); }, nothing },
      { "AbsorptionColor", nothing, [&] { m->SetAbsorptionColor(0.5, nan, 0.5); }, nothing },
      { "Density", nothing, [&] { m->SetDensity(nan); }, nothing },
      { "RefractiveIndex", [&] { m->SetRefractiveIndex(1.33); },
        [&] { m->SetRefractiveIndex(nan); }, [&] { m->SetRefractiveIndex(1); } },
      { "AmbientOcclusionRadius", [&] { m->AmbientOcclusionOn(); },
        [&] { m->SetAmbientOcclusionRadius(nan); }, [&] { m->AmbientOcclusionOff(); } },
      { "FrameBudget", nothing, [&] { m->SetFrameBudget(nan); }, nothing } });
  rmtest::CheckClampCases(log, render,
    { { "Radius", [&](double x) { m->SetRadius(x); }, -1, 0,
        "Radius -1 is outside [0, 1e+15]: clamped to 0" }, // 0: the automatic radius, drawn
      { "Density", [&](double x) { m->SetRadius(0.25), m->SetDensity(x); }, 1e300, 1e15,
        "Density 1e+300 is outside [0, 1e+15]" },
      { "AbsorptionColor", [&](double x) { m->SetDensity(1), m->SetAbsorptionColor(x, x, x); },
        1e300, 1e15, "AbsorptionColor has components outside [0, 1e+15]" },
      { "Color", [&](double x) { m->SetAbsorptionColor(0.5, 0.5, 0.5), m->SetColor(x, 0.5, 0.5); },
        2, 1, "Color has components outside [0, 1]" },
      { "RefractiveIndex", [&](double x) { m->SetColor(0.55, 0.75, 0.95), m->SetRefractiveIndex(x); },
        100, 10, "RefractiveIndex 100 is outside [0.1, 10]" },
      { "AngleResolution", [&](double x) { m->SetRefractiveIndex(1), m->SetAngleResolution(x); },
        0, 0.01, "AngleResolution 0 is outside [0.01, 89]" },
      { "GapThreshold", [&](double x) { m->SetAngleResolution(14), m->SetGapThreshold(x); },
        -3, 0, "GapThreshold -3 is outside" } });
  v.Render();
  log.Silent("the properties restored");
}
}

int TestSPHFluidBadInput(int, char*[])
{
  auto clean = Lattice();
  Viewer v;
  const RGBImage good = v.Show(clean);
  v.Log.Silent("the lattice");
  v.Log.ValidFrame("the lattice");
  v.Log.Check(v.Mapper->GetStatistics()->GetCounter("particles") == 216 &&
      v.Mapper->GetStatistics()->GetCounter("shaded_pixels") > 500,
    "the lattice is drawn");
  Data(v, clean, good);
  Properties(v);
  v.Log.SameImage(v.Render(), good, "everything restored");
  rmtest::CheckDegenerateCameras(v.Log, v.Ren->GetActiveCamera(), [&] { return v.Render(); },
    good, { 51, 102, 153 });

  // A camera inside the fluid: refraction and AO stay finite.
  v.Mapper->SetRadius(0.5);
  v.Mapper->SetRefractiveIndex(1.33);
  v.Mapper->AmbientOcclusionOn();
  vtkCamera* camera = v.Ren->GetActiveCamera();
  camera->SetPosition(0.05, 0.02, 0.1);
  camera->SetFocalPoint(0.3, 0.2, -1);
  v.Ren->ResetCameraClippingRange();
  v.Win->Render();
  v.Log.Check(v.Mapper->GetStatistics()->GetCounter("particles_in_view") > 0 &&
      v.Mapper->GetStatistics()->GetCounter("shaded_pixels") > 0,
    "camera inside: the fluid is seen from the near plane");
  v.Log.ValidFrame("camera inside");

  vtkNew<vtkPolyData> empty;
  v.Mapper->SetInputData(empty);
  v.Ren->ResetCamera();
  v.Win->Render();
  v.Win->Render();
  v.Log.Warned(1, "no points", "empty input");
  return v.Log.Ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
