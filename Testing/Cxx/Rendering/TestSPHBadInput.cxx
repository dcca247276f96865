// vtkSPHVolumeMapper with bad input: an empty point set, missing arrays, NaN positions,
// zero, negative and NaN smoothing lengths, a zero density, a particle straddling the near
// plane. Each gives a clear warning, loses nothing else, and never a NaN or a crash.
//
// usage: TestSPHBadInput
#include "RenderingTestHelpers.h"
#include "vtkRayMapperStatistics.h"
#include "vtkSPHVolumeMapper.h"

#include "vtkColorTransferFunction.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <limits>

int TestSPHBadInput(int, char*[])
{
  bool ok = true;
  auto check = [&](bool condition, const char* what) {
    std::printf("%s %s\n", condition ? "ok  " : "FAIL", what);
    ok = ok && condition;
  };
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0, 0.2, 0.4, 1.0);
  color->AddRGBPoint(10, 1.0, 0.3, 0.2);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0, 0.3);
  opacity->AddPoint(10, 0.8);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  vtkNew<vtkSPHVolumeMapper> mapper;
  mapper->SetSmoothingLength(0.2);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> ren;
  ren->AddVolume(volume);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(96, 96);
  win->AddRenderer(ren);
  rmtest::EventCounter events;
  events.Observe(mapper);

  // A 6^3 lattice with a "value" array (the spheres helper) as the good part.
  auto lattice = rmtest::MakeLattice(6);
  mapper->SetInputData(lattice);
  mapper->SetValueArrayName("value");
  ren->ResetCamera();
  win->Render();
  const auto good = rmtest::ReadRGB(win);
  check(events.Warnings == 0 && mapper->GetStatistics()->GetCounter("particles") == 216,
    "the lattice renders without warnings");

  // Missing arrays: one warning each, with the documented fallback.
  mapper->SetSmoothingLengthArrayName("no-such-h");
  mapper->SetMassArrayName("no-such-mass");
  mapper->SetDensityArrayName("no-such-rho");
  win->Render();
  check(events.Warnings == 2 && rmtest::ReadRGB(win) == good,
    "missing h and mass/density arrays: warned, constant h and volume used (same picture)");
  mapper->SetSmoothingLengthArrayName(nullptr);
  mapper->SetMassArrayName(nullptr);
  mapper->SetDensityArrayName(nullptr);

  // NaN position, bad smoothing lengths, zero density.
  auto bad = rmtest::MakeLattice(6);
  vtkNew<vtkDoubleArray> h;
  h->SetName("h");
  vtkNew<vtkDoubleArray> rho;
  rho->SetName("rho");
  vtkNew<vtkDoubleArray> m;
  m->SetName("m");
  for (vtkIdType i = 0; i < bad->GetNumberOfPoints(); ++i)
  {
    h->InsertNextValue(0.2);
    rho->InsertNextValue(1.0);
    m->InsertNextValue(1.0);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  bad->GetPoints()->SetPoint(3, nan, 0, 0);
  h->SetValue(10, 0.0);
  h->SetValue(11, -0.2);
  h->SetValue(12, nan);
  rho->SetValue(20, 0.0);
  bad->GetPointData()->AddArray(h);
  bad->GetPointData()->AddArray(rho);
  bad->GetPointData()->AddArray(m);
  mapper->SetInputData(bad);
  mapper->SetSmoothingLengthArrayName("h");
  mapper->SetMassArrayName("m");
  mapper->SetDensityArrayName("rho");
  const int before = events.Warnings;
  win->Render();
  const auto rgb = rmtest::ReadRGB(win);
  check(events.Warnings == before + 2 && mapper->GetStatistics()->GetCounter("particles") == 211,
    "NaN position and infinite volume (1 warning), 3 bad smoothing lengths (1 warning); 211 drawn");
  bool drawn = false;
  for (std::size_t k = 0; k < rgb.size(); ++k)
  {
    drawn = drawn || rgb[k] != 0;
  }
  check(drawn, "the rest is drawn");

  // A camera inside the lattice: particles straddle the near plane.
  ren->GetActiveCamera()->SetPosition(0.05, 0.02, 0.1);
  ren->GetActiveCamera()->SetFocalPoint(0.3, 0.2, -1);
  ren->ResetCameraClippingRange();
  win->Render();
  check(mapper->GetStatistics()->GetCounter("particles_in_view") > 0, "camera inside: particles in view");

  // Empty input: a warning, nothing drawn, no crash.
  vtkNew<vtkPolyData> empty;
  const int beforeEmpty = events.Warnings;
  mapper->SetInputData(empty);
  ren->ResetCamera();
  win->Render();
  check(events.Warnings == beforeEmpty + 1, "empty input: one warning");
  check(events.Errors == 0, "no errors");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
