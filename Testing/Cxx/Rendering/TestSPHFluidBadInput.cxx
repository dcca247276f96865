// vtkSPHFluidMapper with bad input: a missing radius array, NaN positions, zero, negative
// and NaN radii, a memory budget too small for one voxel column, a camera inside the fluid,
// an empty point set. Each gives one clear warning, loses nothing else, and never a NaN or a
// crash.
//
// usage: TestSPHFluidBadInput
#include "RenderingTestHelpers.h"
#include "vtkRayMapperStatistics.h"
#include "vtkSPHFluidMapper.h"

#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <limits>

int TestSPHFluidBadInput(int, char*[])
{
  bool ok = true;
  auto check = [&](bool condition, const char* what) {
    std::printf("%s %s\n", condition ? "ok  " : "FAIL", what);
    ok = ok && condition;
  };
  vtkNew<vtkSPHFluidMapper> mapper;
  mapper->SetRadius(0.25);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  vtkNew<vtkVolumeProperty> property;
  volume->SetProperty(property);
  vtkNew<vtkRenderer> ren;
  ren->AddVolume(volume);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(96, 96);
  win->AddRenderer(ren);
  rmtest::EventCounter events;
  events.Observe(mapper);
  vtkRayMapperStatistics* stats = mapper->GetStatistics();

  // A 6^3 lattice as the good part.
  auto lattice = rmtest::MakeLattice(6);
  mapper->SetInputData(lattice);
  ren->ResetCamera();
  win->Render();
  const auto good = rmtest::ReadRGB(win);
  check(events.Warnings == 0 && stats->GetCounter("particles") == 216 &&
      stats->GetCounter("shaded_pixels") > 500,
    "the lattice renders without warnings");

  // A missing radius array: one warning, the constant radius (the same picture).
  mapper->SetRadiusArrayName("no-such-radius");
  win->Render();
  win->Render();
  check(events.Warnings == 1 && rmtest::ReadRGB(win) == good,
    "missing radius array: warned once, constant radius used (same picture)");
  mapper->SetRadiusArrayName(nullptr);

  // NaN positions and bad radii.
  auto bad = rmtest::MakeLattice(6);
  vtkNew<vtkDoubleArray> r;
  r->SetName("r");
  for (vtkIdType i = 0; i < bad->GetNumberOfPoints(); ++i)
  {
    r->InsertNextValue(0.25);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  bad->GetPoints()->SetPoint(3, nan, 0, 0);
  bad->GetPoints()->SetPoint(4, 0, std::numeric_limits<double>::infinity(), 0);
  r->SetValue(10, 0.0);
  r->SetValue(11, -0.2);
  r->SetValue(12, nan);
  bad->GetPointData()->AddArray(r);
  mapper->SetInputData(bad);
  mapper->SetRadiusArrayName("r");
  int before = events.Warnings;
  win->Render();
  const auto rgb = rmtest::ReadRGB(win);
  check(events.Warnings == before + 2 && stats->GetCounter("particles") == 211 &&
      stats->GetCounter("particles_skipped") == 5,
    "2 non-finite positions (1 warning), 3 bad radii (1 warning); 211 drawn");
  long differing = 0;
  for (std::size_t k = 0; k < rgb.size(); ++k)
  {
    differing += rgb[k] != good[k];
  }
  check(differing > 0 && stats->GetCounter("shaded_pixels") > 500, "the rest is drawn");
  win->Render();
  check(events.Warnings == before + 2, "no new warning for the same input");

  // A memory budget that cannot hold one column: one warning, nothing drawn, no crash.
  mapper->SetMemoryBudget(0.0001);
  before = events.Warnings;
  win->Render();
  win->Render();
  check(events.Warnings == before + 1 && stats->GetCounter("budget_exceeded") == 1 &&
      stats->GetCounter("shaded_pixels") == 0,
    "budget too small: one warning, nothing drawn");
  mapper->SetMemoryBudget(512);

  // A camera inside the fluid: refraction and AO stay finite.
  mapper->SetRadius(0.5);
  mapper->SetRadiusArrayName(nullptr);
  mapper->SetInputData(lattice);
  mapper->SetRefractiveIndex(1.33);
  mapper->AmbientOcclusionOn();
  ren->GetActiveCamera()->SetPosition(0.05, 0.02, 0.1);
  ren->GetActiveCamera()->SetFocalPoint(0.3, 0.2, -1);
  ren->ResetCameraClippingRange();
  win->Render();
  check(stats->GetCounter("particles_in_view") > 0 && stats->GetCounter("shaded_pixels") > 0,
    "camera inside: the fluid is seen from the near plane");

  // Empty input: a warning, nothing drawn, no crash.
  vtkNew<vtkPolyData> empty;
  const int beforeEmpty = events.Warnings;
  mapper->SetInputData(empty);
  ren->ResetCamera();
  win->Render();
  win->Render();
  check(events.Warnings == beforeEmpty + 1, "empty input: one warning");
  check(events.Errors == 0, "no errors");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
