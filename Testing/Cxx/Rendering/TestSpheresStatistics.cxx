// Statistics after each render, and "rebuild only on change": a camera, colour, light or
// packet-size change reuses the accelerator; switching accelerators builds only the new
// one, and so does another Embree build quality (the BVH only, not the grid); a radius or point change rebuilds the spheres and the accelerator. Lighting off turns the
// shading effect off.
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"
#include "vtkRayMapperStatistics.h"

#include "vtkActor.h"
#include "vtkLookupTable.h"
#include "vtkProperty.h"

int TestSpheresStatistics(int, char*[])
{
  auto lattice = rmtest::MakeLattice(4);
  vtkNew<vtkCGTSphereMapper> mapper;
  mapper->SetInputData(lattice);
  mapper->SetRadiusArrayName("radius");
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  vtkNew<vtkRenderer> ren;
  ren->AddActor(actor);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(128, 96);
  win->AddRenderer(ren);
  ren->ResetCamera();
  win->Render();

  vtkRayMapperStatistics* s = mapper->GetStatistics();
  std::printf("%s", s->GetSummary());
  RM_CHECK(s->GetCounter("builds") == 1);
  RM_CHECK(s->GetCounter("builds_this_render") == 1);
  RM_CHECK(s->GetCounter("spheres") == 64);
  RM_CHECK(s->GetCounter("rays") == 128 * 96);
  RM_CHECK(s->GetCounter("hits") > 0 && s->GetCounter("hits") < 128 * 96);
  RM_CHECK(s->GetEffect("shading"));
  RM_CHECK(s->GetPhaseTime("trace") > 0);
  RM_CHECK(s->GetNumberOfCounters() >= 5);

  // Camera move: no rebuild.
  ren->GetActiveCamera()->Azimuth(30);
  ren->ResetCameraClippingRange();
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 1);
  RM_CHECK(s->GetCounter("builds_this_render") == 0);
  RM_CHECK(s->GetPhaseTime("spheres") == 0 && s->GetPhaseTime("grid_build") == 0);

  // New lookup table: colours change, the BVH does not.
  vtkNew<vtkLookupTable> lut;
  lut->SetHueRange(0.1, 0.5);
  lut->Build();
  mapper->SetLookupTable(lut);
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 1);

  // Lighting off: no shading effect.
  actor->GetProperty()->LightingOff();
  win->Render();
  RM_CHECK(!s->GetEffect("shading"));
  RM_CHECK(!s->GetEffect("specular"));
  RM_CHECK(s->GetCounter("builds") == 1);

  // Another packet size: nothing to rebuild. Another accelerator: that accelerator only.
  mapper->SetPacketSize(4);
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 1);
  mapper->SetAcceleratorToEmbree();
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 2);
  RM_CHECK(s->GetPhaseTime("bvh_build") > 0 && s->GetPhaseTime("spheres") == 0);
  // Another Embree build quality: the BVH again (not the spheres); the same quality: nothing.
  mapper->SetEmbreeBuildQuality(2);
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 3);
  RM_CHECK(s->GetPhaseTime("bvh_build") > 0 && s->GetPhaseTime("spheres") == 0);
  mapper->SetEmbreeBuildQuality(2);
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 3);
  mapper->SetAcceleratorToCoherentGrid();
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 4);
  // The grid does not depend on Embree's build quality.
  mapper->SetEmbreeBuildQuality(0);
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 4);
  RM_CHECK(s->GetCounter("grid_cells") > 0 && s->GetCounter("cells") > 0);

  // Parameter ranges: only the lattice values in [10, 30] are drawn, and moving the
  // bounds never rebuilds anything.
  const auto before = rmtest::ReadRGB(win);
  mapper->SetRange(0, "value", 10, 30);
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 5); // the range's array: a new sphere set and grid
  RM_CHECK(s->GetEffect("range_culling") && s->GetCounter("range_culled") > 0);
  RM_CHECK(s->GetCounter("hits") < 128 * 96);
  mapper->SetRange(0, "value", 0, 63);
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 5);
  RM_CHECK(rmtest::ReadRGB(win) == before); // every value in range: the full picture
  mapper->RemoveAllRanges();
  win->Render();
  RM_CHECK(!s->GetEffect("range_culling") && s->GetCounter("range_culled") == 0);
  RM_CHECK(s->GetCounter("builds") == 6);

  // Radius scale and moved points rebuild.
  mapper->SetRadiusScale(0.5);
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 7);
  lattice->GetPoints()->SetPoint(0, 0.1, 0.2, 0.3);
  lattice->GetPoints()->Modified();
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 8);
  std::printf("%s", s->GetSummary());
  return EXIT_SUCCESS;
}
