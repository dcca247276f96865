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

namespace
{
// The automatic accelerator (the default): the grid where its leaves separate the spheres,
// Embree's BVH where more than 1% of them crowd leaves of more than 1024 (here 1500 of 1564
// spheres in one point, shells of radii 0.1 to 0.5 around it), the same picture either way.
int TestAutomaticAccelerator()
{
  vtkNew<vtkCGTSphereMapper> mapper;
  RM_CHECK(mapper->GetAccelerator() == VTK_CGT_ACCELERATOR_AUTOMATIC);
  auto lattice = rmtest::MakeLattice(4);
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
  RM_CHECK(s->GetCounter("accelerator_embree") == 0 && s->GetCounter("grid_cells") > 0);
  RM_CHECK(s->GetCounter("grid_crowded_spheres") == 0);

  std::vector<std::array<double, 3>> centers(1500, { 0.2, -0.1, 0.3 });
  std::vector<double> radii(1500);
  for (std::size_t i = 0; i < radii.size(); ++i)
  {
    radii[i] = 0.1 + 0.4 * static_cast<double>(i) / 1499.0; // no two alike: no ties
  }
  for (vtkIdType i = 0; i < lattice->GetNumberOfPoints(); ++i)
  {
    std::array<double, 3> p;
    lattice->GetPoint(i, p.data());
    centers.push_back({ 2 * p[0], 2 * p[1], 2 * p[2] });
    radii.push_back(0.15);
  }
  mapper->SetInputData(rmtest::MakeSpheres(centers, radii));
  ren->ResetCamera();
  win->Render();
  RM_CHECK(s->GetCounter("accelerator_embree") == 1);
  RM_CHECK(s->GetCounter("grid_crowded_spheres") == 1500 && s->GetCounter("grid_cells") == 0);
  RM_CHECK(s->GetPhaseTime("grid_build") > 0 && s->GetPhaseTime("bvh_build") > 0);
  const auto automatic = rmtest::ReadRGB(win);
  mapper->SetAcceleratorToCoherentGrid();
  win->Render();
  RM_CHECK(s->GetCounter("accelerator_embree") == 0 && s->GetCounter("grid_crowded_spheres") == 1500);
  RM_CHECK(rmtest::ReadRGB(win) == automatic);
  mapper->SetAcceleratorToEmbree();
  win->Render();
  RM_CHECK(s->GetCounter("accelerator_embree") == 1 && s->GetPhaseTime("grid_build") == 0);
  RM_CHECK(rmtest::ReadRGB(win) == automatic);
  return EXIT_SUCCESS;
}
}

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
  return TestAutomaticAccelerator();
}
